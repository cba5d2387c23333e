#include "mpm/core/parallel.hpp"

#include <sched.h>
#ifdef __linux__
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace mpm {

namespace {

/// How long a thread with nothing to do spins before it sleeps. It bridges the serial work between the loops
/// of a step (a few microseconds) without a wake-up; a thread that shares its core with another process gives
/// it back soon after. OpenMP runtimes spin about 100 times longer by default, which is what made a 2-thread
/// run with one core busy 4-10x slower than a 1-thread run (docs/performance.md, "Sharing the machine").
constexpr auto spin_time = std::chrono::microseconds(50);
/// Chunks a loop is cut into per thread: enough that a thread set aside by the operating system holds up at
/// most one small chunk, few enough that claiming them costs nothing measurable. With at most 512 threads a
/// loop has fewer than 2^16 chunks, the room the claim word gives them.
constexpr std::ptrdiff_t chunks_per_thread = 16;

void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield");
#endif
}

/// Spin until ready() or the spin time has passed; whether ready() came true.
template <class Ready>
bool spin_until(Ready&& ready) {
  const auto until = std::chrono::steady_clock::now() + spin_time;
  for (;;) {
    for (int k = 0; k < 64; ++k) {
      if (ready()) return true;
      relax();
    }
    if (std::chrono::steady_clock::now() >= until) return ready();
  }
}

/// Sleep while `word` holds `expected` (or until woken, or spuriously: callers check again). On Linux a futex
/// on the word itself, without the shared table of waiters std::atomic's wait keeps in libstdc++.
void sleep_while(std::atomic<std::uint32_t>& word, std::uint32_t expected) {
#ifdef __linux__
  static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t) &&
                std::atomic<std::uint32_t>::is_always_lock_free);
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAIT_PRIVATE, expected, nullptr, nullptr,
          0);
#else
  word.wait(expected);
#endif
}

/// Wake the threads sleeping on `word`.
void wake_all(std::atomic<std::uint32_t>& word) {
#ifdef __linux__
  syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(&word), FUTEX_WAKE_PRIVATE, INT_MAX, nullptr, nullptr,
          0);
#else
  word.notify_all();
#endif
}

int default_threads() {
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (end != env && n > 0) return static_cast<int>(std::min<long>(n, max_threads));
  }
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

thread_local int this_thread_index = 0;
thread_local bool inside_loop = false;

/// threads - 1 workers and the thread that starts a loop claim its chunks. Each thread has a home range of
/// chunks, the same part of every loop as a static division gives it (so a pass finds in its core's cache
/// what the pass before left there), which it takes from the front; a thread whose home range is done takes
/// chunks from the back of another's, so a thread the operating system has set aside holds up one chunk at
/// most. A loop is published as an epoch, and each range's claim word holds the epoch beside the range's
/// bounds, so that a thread still in an earlier loop, or one that wakes after its loop has ended, claims
/// nothing; the starting thread waits only for chunks already claimed, not for workers.
class Pool {
 public:
  explicit Pool(int threads) : ranges_(std::make_unique<Range[]>(static_cast<std::size_t>(threads))) {
    for (int k = 1; k < threads; ++k) workers_.emplace_back([this, k] { work(k); });
  }
  ~Pool() {
    stop_.store(true, std::memory_order_relaxed);
    epoch_.fetch_add(1, std::memory_order_seq_cst);
    wake_all(epoch_);
    for (std::thread& w : workers_) w.join();
  }
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  bool run(std::ptrdiff_t n, detail::ChunkRunner runner, void* body) {
    if (inside_loop || busy_.test_and_set(std::memory_order_acquire)) return false;
    const int t = threads();
    const std::ptrdiff_t chunks = std::min<std::ptrdiff_t>(n, chunks_per_thread * t);
    runner_.store(runner, std::memory_order_relaxed);
    body_.store(body, std::memory_order_relaxed);
    n_.store(n, std::memory_order_relaxed);
    chunks_.store(chunks, std::memory_order_relaxed);
    failure_ = nullptr;
    failed_.store(false, std::memory_order_relaxed);
    remaining_.store(static_cast<std::uint32_t>(chunks), std::memory_order_relaxed);
    const std::uint32_t e = epoch_.load(std::memory_order_relaxed) + 1;
    for (int k = 0; k < t; ++k)
      ranges_[k].word.store(pack(e, k * chunks / t, (k + 1) * chunks / t), std::memory_order_release);
    epoch_.store(e, std::memory_order_seq_cst);
    if (sleepers_.load(std::memory_order_seq_cst) > 0) wake_all(epoch_);
    work_on(e, 0);
    if (!spin_until([&] { return remaining_.load(std::memory_order_acquire) == 0; })) {
      waiting_.store(true, std::memory_order_seq_cst);
      for (std::uint32_t r; (r = remaining_.load(std::memory_order_seq_cst)) != 0;)
        sleep_while(remaining_, r);
      waiting_.store(false, std::memory_order_relaxed);
    }
    const std::exception_ptr failure = failure_;
    busy_.clear(std::memory_order_release);
    if (failure) std::rethrow_exception(failure);
    return true;
  }

 private:
  /// A claim word: the epoch (bits 32-63), the range's first unclaimed chunk (16-31) and its end (0-15).
  struct alignas(64) Range {
    std::atomic<std::uint64_t> word{0};
  };
  static std::uint64_t pack(std::uint32_t epoch, std::ptrdiff_t front, std::ptrdiff_t back) {
    return std::uint64_t{epoch} << 32 | static_cast<std::uint64_t>(front) << 16 |
           static_cast<std::uint64_t>(back);
  }

  /// Claim chunk `k` of epoch e from range r: its front (the owner) or its back (another thread).
  bool claim(int r, std::uint32_t e, bool front, std::ptrdiff_t& k) {
    std::atomic<std::uint64_t>& word = ranges_[r].word;
    std::uint64_t c = word.load(std::memory_order_acquire);
    for (;;) {
      const std::uint64_t first = (c >> 16) & 0xffffu, end = c & 0xffffu;
      if (static_cast<std::uint32_t>(c >> 32) != e || first >= end) return false;
      const std::uint64_t next = front ? c + (std::uint64_t{1} << 16) : c - 1;
      if (word.compare_exchange_weak(c, next, std::memory_order_acq_rel, std::memory_order_acquire)) {
        k = static_cast<std::ptrdiff_t>(front ? first : end - 1);
        return true;
      }
    }
  }

  /// Claim and run chunks of epoch e as thread `self` until none is left.
  void work_on(std::uint32_t e, int self) {
    inside_loop = true;
    const int t = threads();
    std::ptrdiff_t k = 0;
    for (;;) {
      bool found = claim(self, e, true, k);
      for (int j = 1; j < t && !found; ++j) found = claim((self + j) % t, e, false, k);
      if (!found) break;
      run_chunk(k);
    }
    inside_loop = false;
  }

  /// Run chunk k of the current loop, which cannot end before it is done: its description stays valid.
  void run_chunk(std::ptrdiff_t k) {
    const std::ptrdiff_t n = n_.load(std::memory_order_relaxed),
                         chunks = chunks_.load(std::memory_order_relaxed);
    if (!failed_.load(std::memory_order_relaxed)) {
      try {
        runner_.load(std::memory_order_relaxed)(body_.load(std::memory_order_relaxed), k * n / chunks,
                                                (k + 1) * n / chunks);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex_);
        if (!failure_) failure_ = std::current_exception();
        failed_.store(true, std::memory_order_relaxed);
      }
    }
    if (remaining_.fetch_sub(1, std::memory_order_seq_cst) == 1 && waiting_.load(std::memory_order_seq_cst))
      wake_all(remaining_);
  }

  void work(int index) {
    this_thread_index = index;
    std::uint32_t seen = 0;
    for (;;) {
      if (!spin_until([&] { return epoch_.load(std::memory_order_acquire) != seen; })) {
        sleepers_.fetch_add(1, std::memory_order_seq_cst);
        while (epoch_.load(std::memory_order_seq_cst) == seen) sleep_while(epoch_, seen);
        sleepers_.fetch_sub(1, std::memory_order_relaxed);
      }
      seen = epoch_.load(std::memory_order_acquire);
      if (stop_.load(std::memory_order_relaxed)) return;
      work_on(seen, index);
    }
  }

  std::vector<std::thread> workers_;
  std::unique_ptr<Range[]> ranges_;
  std::atomic_flag busy_ = ATOMIC_FLAG_INIT;
  std::atomic<std::uint32_t> epoch_{0};
  std::atomic<std::uint32_t> remaining_{0};  ///< chunks not yet done (at most chunks_per_thread x 512)
  std::atomic<int> sleepers_{0};
  std::atomic<bool> waiting_{false}, stop_{false}, failed_{false};
  std::atomic<detail::ChunkRunner> runner_{nullptr};
  std::atomic<void*> body_{nullptr};
  std::atomic<std::ptrdiff_t> n_{0}, chunks_{0};
  std::mutex failure_mutex_;
  std::exception_ptr failure_;
};

std::mutex pool_mutex;
int configured_threads = 0;  // 0: not yet set
std::unique_ptr<Pool> pool;

int threads_locked() {
  if (configured_threads == 0) configured_threads = default_threads();
  return configured_threads;
}

}  // namespace

namespace detail {
bool run_chunks(std::ptrdiff_t n, ChunkRunner run, void* body) {
  if (inside_loop) return false;
  Pool* p = nullptr;
  {
    const std::lock_guard<std::mutex> lock(pool_mutex);
    if (threads_locked() == 1) return false;
    if (!pool || pool->threads() != configured_threads) {
      pool.reset();
      pool = std::make_unique<Pool>(configured_threads);
    }
    p = pool.get();
  }
  return p->run(n, run, body);
}
}  // namespace detail

void set_num_threads(int n) {
  const std::lock_guard<std::mutex> lock(pool_mutex);
  configured_threads = n > 0 ? std::min(n, max_threads) : default_threads();
}

int num_threads() {
  const std::lock_guard<std::mutex> lock(pool_mutex);
  return threads_locked();
}

int thread_index() {
  return this_thread_index;
}

}  // namespace mpm
