#include "mpm/distributed/communicator.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>

#ifdef MPM_WITH_MPI
#include <mpi.h>
#endif

namespace mpm {
namespace {

/// The value of a whole-number environment variable, or `otherwise` when it is unset or not a number.
long env_number(const char* name, long otherwise) {
  const char* text = std::getenv(name);
  if (!text || !*text) return otherwise;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  return *end ? otherwise : value;
}

/// Size and rank variables of the launchers: OpenMPI's mpirun, MPICH's mpiexec (PMI), Slurm's srun.
constexpr std::pair<const char*, const char*> launcher_variables[] = {
    {"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"},
    {"PMI_SIZE", "PMI_RANK"},
    {"SLURM_STEP_NUM_TASKS", "SLURM_PROCID"}};

#ifdef MPM_WITH_MPI
/// A failed MPI call: MPI's default handler aborts every rank with its message first, so this is not reached
/// unless the handler was changed.
void check(int status, const char* call) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + call + " failed");
}

class MpiWorld final : public Communicator {
  /// Adds the seconds of its lifetime to the world's time in communication.
  struct Timer {
    double& total;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    ~Timer() { total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
  };
  mutable double seconds_ = 0;
  mutable std::int64_t bytes_ = 0;

 public:
  double seconds() const override { return seconds_; }
  std::int64_t bytes_sent() const override { return bytes_; }
  int rank() const override {
    int r = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
  }
  int size() const override {
    int s = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &s);
    return s;
  }
  double max(double x) const override {
    const Timer timer{seconds_};
    double out = x;
    check(MPI_Allreduce(&x, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }
  std::int64_t min(std::int64_t n) const override {
    const Timer timer{seconds_};
    std::int64_t out = n;
    check(MPI_Allreduce(&n, &out, 1, MPI_INT64_T, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce");
    return out;
  }
  void sum(std::vector<std::int64_t>& a) const override {
    const Timer timer{seconds_};
    check(MPI_Allreduce(MPI_IN_PLACE, a.data(), static_cast<int>(a.size()), MPI_INT64_T, MPI_SUM,
                        MPI_COMM_WORLD),
          "MPI_Allreduce");
  }
  std::vector<std::vector<std::byte>> exchange(const std::vector<std::vector<std::byte>>& to) const override {
    const Timer timer{seconds_};
    const int n = size();
    std::vector<int> send_count(n), recv_count(n), send_at(n), recv_at(n);
    const int me = rank();
    for (int r = 0; r < n; ++r) {
      send_count[r] = static_cast<int>(to[r].size());
      if (r != me) bytes_ += send_count[r];
    }
    check(MPI_Alltoall(send_count.data(), 1, MPI_INT, recv_count.data(), 1, MPI_INT, MPI_COMM_WORLD),
          "MPI_Alltoall");
    std::vector<std::byte> send, recv;
    int s = 0, q = 0;
    for (int r = 0; r < n; ++r) {
      send_at[r] = s;
      recv_at[r] = q;
      s += send_count[r];
      q += recv_count[r];
      send.insert(send.end(), to[r].begin(), to[r].end());
    }
    recv.resize(static_cast<std::size_t>(q));
    check(MPI_Alltoallv(send.data(), send_count.data(), send_at.data(), MPI_BYTE, recv.data(),
                        recv_count.data(), recv_at.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Alltoallv");
    std::vector<std::vector<std::byte>> from(static_cast<std::size_t>(n));
    for (int r = 0; r < n; ++r)
      from[r].assign(recv.begin() + recv_at[r], recv.begin() + recv_at[r] + recv_count[r]);
    return from;
  }
  std::vector<std::vector<std::byte>> exchange_with(
      const std::vector<int>& peers, const std::vector<std::vector<std::byte>>& to) const override {
    const Timer timer{seconds_};
    // The sizes first, then the bytes; each round's tag keeps its messages apart from the other's.
    constexpr int size_tag = 1, bytes_tag = 2;
    const std::size_t n = peers.size();
    std::vector<std::int64_t> send_size(n), recv_size(n);
    std::vector<MPI_Request> requests(2 * n);
    for (std::size_t k = 0; k < n; ++k) {
      send_size[k] = static_cast<std::int64_t>(to[k].size());
      bytes_ += send_size[k];
      check(MPI_Irecv(&recv_size[k], 1, MPI_INT64_T, peers[k], size_tag, MPI_COMM_WORLD, &requests[k]),
            "MPI_Irecv");
      check(MPI_Isend(&send_size[k], 1, MPI_INT64_T, peers[k], size_tag, MPI_COMM_WORLD, &requests[n + k]),
            "MPI_Isend");
    }
    check(MPI_Waitall(static_cast<int>(2 * n), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    std::vector<std::vector<std::byte>> from(n);
    for (std::size_t k = 0; k < n; ++k) {
      from[k].resize(static_cast<std::size_t>(recv_size[k]));
      check(MPI_Irecv(from[k].data(), static_cast<int>(recv_size[k]), MPI_BYTE, peers[k], bytes_tag,
                      MPI_COMM_WORLD, &requests[k]),
            "MPI_Irecv");
      check(MPI_Isend(to[k].data(), static_cast<int>(send_size[k]), MPI_BYTE, peers[k], bytes_tag,
                      MPI_COMM_WORLD, &requests[n + k]),
            "MPI_Isend");
    }
    check(MPI_Waitall(static_cast<int>(2 * n), requests.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    return from;
  }
  std::vector<std::byte> broadcast(std::vector<std::byte> bytes, int root) const override {
    const Timer timer{seconds_};
    std::int64_t length = static_cast<std::int64_t>(bytes.size());
    check(MPI_Bcast(&length, 1, MPI_INT64_T, root, MPI_COMM_WORLD), "MPI_Bcast");
    bytes.resize(static_cast<std::size_t>(length));
    check(MPI_Bcast(bytes.data(), static_cast<int>(length), MPI_BYTE, root, MPI_COMM_WORLD), "MPI_Bcast");
    return bytes;
  }
};
#endif

bool mpi_active = false;

}  // namespace

std::string broadcast_text(const Communicator& comm, const std::string& text, int root) {
  const auto* first = reinterpret_cast<const std::byte*>(text.data());
  const std::vector<std::byte> bytes =
      comm.broadcast(std::vector<std::byte>(first, first + text.size()), root);
  std::string out(bytes.size(), '\0');
  std::transform(bytes.begin(), bytes.end(), out.begin(), [](std::byte b) { return static_cast<char>(b); });
  return out;
}

std::string first_failure(const Communicator& comm, const std::string& failure) {
  const std::int64_t first = comm.min(failure.empty() ? comm.size() : comm.rank());
  return first == comm.size() ? std::string() : broadcast_text(comm, failure, static_cast<int>(first));
}

const Communicator& one_process() {
  static const Alone one;
  return one;
}

const Communicator& world() {
#ifdef MPM_WITH_MPI
  static const MpiWorld mpi;
  if (mpi_active) return mpi;
#endif
  return one_process();
}

int launched_size() {
  for (const auto& [size, rank] : launcher_variables)
    if (env_number(size, 1) > 1) return static_cast<int>(env_number(size, 1));
  return 1;
}

int launched_rank() {
  for (const auto& [size, rank] : launcher_variables)
    if (env_number(size, 1) > 1) return static_cast<int>(env_number(rank, 0));
  return 0;
}

bool built_with_mpi() {
#ifdef MPM_WITH_MPI
  return true;
#else
  return false;
#endif
}

MpiSession::MpiSession([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
#ifdef MPM_WITH_MPI
  if (launched_size() <= 1) return;
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  active_ = mpi_active = true;
#endif
}

MpiSession::~MpiSession() {
#ifdef MPM_WITH_MPI
  if (active_) MPI_Finalize();
  mpi_active = false;
#endif
}

}  // namespace mpm
