#pragma once
// The process group a run is spread over (issue 15, docs/mpi.md). Built with SHATTER_MPI this
// wraps MPI_COMM_WORLD; without it, and in a plain `shatter run` started without mpirun
// (OpenMPI's singleton), it is one rank and every collective returns its input, so the
// single-process engine makes no MPI call at all.
//
// Every collective here is blocking and must be called by all ranks in the same order; the
// engine calls them only from stages that are ordered one after the other in its step graph
// (MPI_THREAD_SERIALIZED: one thread at a time, whichever TBB worker runs the stage).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace shatter::parallel {

// Traffic counters of the exchanges (halo, migration, gathers): bytes and point-to-point
// messages this rank sent, and seconds spent inside the exchange calls.
struct Traffic {
  std::uint64_t bytes = 0;
  std::uint64_t messages = 0;
  double seconds = 0.0;
};

using Bytes = std::vector<std::byte>;

class Comm {
 public:
  int rank() const { return rank_; }
  int size() const { return size_; }
  // More than one rank: the engine decomposes the grid only then.
  bool distributed() const { return size_ > 1; }

  double max(double v) const;
  double min(double v) const;
  std::int64_t sum(std::int64_t v) const;
  // Element-wise sums (exact: integers).
  void sum(std::span<std::int64_t> v) const;
  void max(std::span<double> v) const;
  // All ranks get every rank's values, rank by rank.
  std::vector<std::int64_t> allgather(std::span<const std::int64_t> mine) const;

  // Sparse exchange: send[r] goes to rank r (empty: no message); returns what each rank sent
  // here. One count exchange (MPI_Alltoall) then one message per non-empty buffer.
  std::vector<Bytes> exchange(const std::vector<Bytes>& send, Traffic* traffic = nullptr) const;
  // Point-to-point exchange where both sides know the sizes: recv[r] must be sized already.
  void exchange_known(const std::vector<Bytes>& send, std::vector<Bytes>& recv,
                      Traffic* traffic = nullptr) const;
  // Rank 0 gets every rank's buffer (others get nothing).
  std::vector<Bytes> gather(const Bytes& mine) const;
  // Everyone gets root's buffer.
  void broadcast(Bytes& data, int root = 0) const;
  void barrier() const;

  // Ends every rank with this exit code (MPI_Abort); a single process just exits.
  [[noreturn]] void abort(int code) const;

  // Set once by init().
  int rank_ = 0;
  int size_ = 1;
};

// The world group (rank 0 of 1 until init() runs).
const Comm& world();
// True when the program was built with MPI (SHATTER_MPI).
bool built_with_mpi();
// Initialises MPI when built with it (MPI_THREAD_SERIALIZED); harmless without. finalize()
// must be called before a normal exit of a program that called init().
void init(int* argc, char*** argv);
void finalize();

// Byte packing helpers for the exchanges.
template <class T>
void put(Bytes& b, const T& v) {
  const auto* p = reinterpret_cast<const std::byte*>(&v);
  b.insert(b.end(), p, p + sizeof(T));
}
template <class T>
void put(Bytes& b, const T* v, std::size_t n) {
  const auto* p = reinterpret_cast<const std::byte*>(v);
  b.insert(b.end(), p, p + n * sizeof(T));
}
class Reader {
 public:
  explicit Reader(const Bytes& b) : b_(b) {}
  template <class T>
  T get() {
    T v;
    copy(&v, 1);
    return v;
  }
  template <class T>
  void copy(T* out, std::size_t n);
  bool done() const { return at_ >= b_.size(); }

 private:
  const Bytes& b_;
  std::size_t at_ = 0;
};

}  // namespace shatter::parallel

#include <cstring>
#include <stdexcept>

namespace shatter::parallel {
template <class T>
void Reader::copy(T* out, std::size_t n) {
  if (at_ + n * sizeof(T) > b_.size()) throw std::runtime_error("parallel: message too short");
  std::memcpy(out, b_.data() + at_, n * sizeof(T));
  at_ += n * sizeof(T);
}
}  // namespace shatter::parallel
