#pragma once
/// The communication points of a run, named even in one process: the ranks a run is divided between and the
/// few collective operations the explicit step needs. One process is a communicator of one rank whose
/// operations return their arguments; an MPI build started under mpirun or srun gets the world's ranks
/// (world()).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mpm {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// The largest of every rank's x (exact: a maximum does not round, so any order gives the same bits).
  virtual double max(double x) const = 0;
  /// The smallest of every rank's n.
  virtual std::int64_t min(std::int64_t n) const = 0;
  /// Every rank's a added element by element (integers: exact in any order). All ranks pass the same length.
  virtual void sum(std::vector<std::int64_t>& a) const = 0;
  /// Send to[r] to rank r (to.size() == size()); returns from, from[r] what rank r sent to this one.
  virtual std::vector<std::vector<std::byte>> exchange(
      const std::vector<std::vector<std::byte>>& to) const = 0;
  /// Send to[k] to rank peers[k] and receive one message from each of them: returns from, from[k] what
  /// peers[k] sent (possibly nothing). Every peer lists this rank among its own peers (the relation is
  /// symmetric), and no rank lists itself. Messages between the peers only: the cost grows with the peers,
  /// not with the ranks.
  virtual std::vector<std::vector<std::byte>> exchange_with(
      const std::vector<int>& peers, const std::vector<std::vector<std::byte>>& to) const = 0;
  /// Rank root's bytes, on every rank.
  virtual std::vector<std::byte> broadcast(std::vector<std::byte> bytes, int root) const = 0;
  /// Wall-clock seconds this rank has spent in the operations above (waiting for the others included).
  virtual double seconds() const = 0;
  /// Bytes this rank has sent to other ranks in exchange() and exchange_with() (the halo sums and the
  /// migrating particles).
  virtual std::int64_t bytes_sent() const = 0;
};

/// Rank `rank` of `size` talking to no one: every operation returns this rank's own argument (exchange()
/// hands back what it was given). One process is rank 0 of 1 (one_process()); tests play the ranks of a
/// division in one process with others.
class Alone : public Communicator {
 public:
  explicit Alone(int rank = 0, int size = 1) : rank_(rank), size_(size) {}
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  double max(double x) const override { return x; }
  std::int64_t min(std::int64_t n) const override { return n; }
  void sum(std::vector<std::int64_t>&) const override {}
  std::vector<std::vector<std::byte>> exchange(const std::vector<std::vector<std::byte>>& to) const override {
    return to;
  }
  std::vector<std::vector<std::byte>> exchange_with(
      const std::vector<int>& peers, const std::vector<std::vector<std::byte>>&) const override {
    return std::vector<std::vector<std::byte>>(peers.size());
  }
  std::vector<std::byte> broadcast(std::vector<std::byte> bytes, int) const override { return bytes; }
  double seconds() const override { return 0; }
  std::int64_t bytes_sent() const override { return 0; }

 private:
  int rank_, size_;
};

/// Rank root's text, on every rank.
std::string broadcast_text(const Communicator& comm, const std::string& text, int root);

/// The failure (a message, empty for none) of the lowest rank that failed, on every rank; empty when none
/// did.
std::string first_failure(const Communicator& comm, const std::string& failure);

/// One process: Alone, rank 0 of 1.
const Communicator& one_process();

/// The ranks this process runs among: MPI's world when the build has MPI and a launcher started several
/// processes (MpiSession must be alive), otherwise one_process().
const Communicator& world();

/// Initialises MPI for the process's lifetime when the build has MPI and a launcher (mpirun, srun) started
/// this process among several; does nothing otherwise. Threads inside a rank do not call MPI
/// (MPI_THREAD_FUNNELED).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  /// Whether MPI was initialised (several processes started by a launcher, in an MPI build).
  bool active() const { return active_; }

 private:
  bool active_ = false;
};

/// The number of processes a launcher started (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_SIZE... when set), 1
/// when none did; and this process's rank among them.
int launched_size();
int launched_rank();

/// Whether this build can run among several processes.
bool built_with_mpi();

}  // namespace mpm
