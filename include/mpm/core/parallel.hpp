#pragma once
/// The one parallel loop helper: kernels are written as loop bodies over an index range, run by the program's
/// own thread pool (src/core/parallel.cpp). A loop is cut into chunks that the threads claim one at a time,
/// so a thread that the operating system has set aside (another process busy on its core) leaves its share to
/// the others instead of holding every loop up; a thread with nothing to do spins for a short, fixed time and
/// then sleeps, giving its core back (docs/performance.md, "Sharing the machine").
#include <algorithm>
#include <cstddef>
#include <memory>
#include <type_traits>
#include <vector>

namespace mpm {

namespace detail {
/// Runs the loop body at `body` over indices [begin, end).
using ChunkRunner = void (*)(void* body, std::ptrdiff_t begin, std::ptrdiff_t end);
/// Run [0, n) in chunks on the pool's threads and the calling one, and return true; or return false, having
/// run nothing, where the loop must run on the calling thread alone: one thread, a loop inside a loop of the
/// pool, or another thread's loop in progress. An exception from the body stops the claiming of further
/// chunks and is rethrown here once the chunks in progress are done.
bool run_chunks(std::ptrdiff_t n, ChunkRunner run, void* body);
}  // namespace detail

/// Run fn(i) for i in [0, n) on all threads; loops shorter than `min_parallel` run on the calling thread
/// (waking threads costs more than small loops gain). Bodies must not depend on which thread runs which
/// index.
template <class Fn>
void parallel_for(std::ptrdiff_t n, Fn&& fn, std::ptrdiff_t min_parallel = 1024) {
  using Body = std::remove_reference_t<Fn>;
  const detail::ChunkRunner run = [](void* body, std::ptrdiff_t begin, std::ptrdiff_t end) {
    Body& f = *static_cast<Body*>(body);
    for (std::ptrdiff_t i = begin; i < end; ++i) f(i);
  };
  if (n >= min_parallel &&
      detail::run_chunks(n, run, const_cast<void*>(static_cast<const void*>(std::addressof(fn)))))
    return;
  for (std::ptrdiff_t i = 0; i < n; ++i) fn(i);
}

/// combine(...combine(combine(identity, value(0)), value(1))..., value(n - 1)) grouped in fixed blocks of
/// indices: the blocks' results are combined in order, so the result is the same bits for any thread count.
template <class T, class Value, class Combine>
T parallel_reduce(std::ptrdiff_t n, T identity, Value&& value, Combine&& combine) {
  constexpr std::ptrdiff_t block = 4096;
  const std::ptrdiff_t blocks = (n + block - 1) / block;
  std::vector<T> partial(static_cast<std::size_t>(blocks), identity);
  parallel_for(
      blocks,
      [&](std::ptrdiff_t b) {
        T acc = identity;
        for (std::ptrdiff_t i = b * block; i < std::min(n, (b + 1) * block); ++i)
          acc = combine(acc, value(i));
        partial[static_cast<std::size_t>(b)] = acc;
      },
      2);
  T acc = identity;
  for (const T& p : partial) acc = combine(acc, p);
  return acc;
}

/// Set the number of threads parallel_for uses; 0 restores the default: OMP_NUM_THREADS where it is set (a
/// positive integer), else the cores this process may run on.
/// The most threads a run takes: each entry (--threads, simulation.threads, Python's threads=) refuses more.
inline constexpr int max_threads = 512;

void set_num_threads(int n);

/// The number of threads parallel_for will use.
int num_threads();

/// The calling thread's index in the pool's loops: 0 for the thread that started the loop (and outside
/// loops), 1 ... num_threads() - 1 for the pool's own.
int thread_index();

}  // namespace mpm
