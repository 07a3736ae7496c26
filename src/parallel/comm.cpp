#include "shatter/parallel/comm.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits>

#ifdef SHATTER_HAVE_MPI
// The C API only (OpenMPI's mpi.h would otherwise pull in the removed C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace shatter::parallel {
namespace {

Comm g_world;
#ifdef SHATTER_HAVE_MPI
bool g_initialised = false;
#endif

#ifdef SHATTER_HAVE_MPI
struct Timer {
  Traffic* t;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  ~Timer() {
    if (t)
      t->seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
};
int as_int(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw std::runtime_error("parallel: one message over 2 GiB");
  }
  return static_cast<int>(n);
}
// Every rank's n values of `type` combined by `op`, in place (MPI_Allreduce).
void allreduce_in_place(void* data, std::size_t n, MPI_Datatype type, MPI_Op op) {
  MPI_Allreduce(MPI_IN_PLACE, data, as_int(n), type, op, MPI_COMM_WORLD);
}
#endif

}  // namespace

const Comm& world() {
  return g_world;
}

bool built_with_mpi() {
#ifdef SHATTER_HAVE_MPI
  return true;
#else
  return false;
#endif
}

void init(int* argc, char*** argv) {
#ifdef SHATTER_HAVE_MPI
  // Only under a launcher (mpirun, srun): a plain `shatter ...` stays an ordinary process. An
  // OpenMPI singleton MPI_Init costs about a second per start, and the CLI and Python tests start
  // the program hundreds of times.
  bool launched = false;
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    launched = launched || std::getenv(v) != nullptr;
  }
  if (!launched) return;
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
  g_initialised = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_world.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &g_world.size_);
  // Errors end the run through the engine's own reports (Comm::abort), not MPI's handler.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
  if (provided < MPI_THREAD_SERIALIZED && g_world.size_ > 1) {
    throw std::runtime_error("MPI does not provide MPI_THREAD_SERIALIZED");
  }
#else
  (void)argc;
  (void)argv;
  // Started by mpirun on several ranks without the MPI path: every rank would run the whole
  // scene into the same directory.
  const char* n = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (n == nullptr) n = std::getenv("PMI_SIZE");
  if (n != nullptr && std::atoi(n) > 1) {
    std::fputs(
        "shatter was built without MPI (SHATTER_MPI=OFF or no MPI found): run it without "
        "mpirun, or rebuild with MPI (docs/mpi.md)\n",
        stderr);
    std::exit(2);
  }
#endif
}

void finalize() {
#ifdef SHATTER_HAVE_MPI
  if (g_initialised) {
    int done = 0;
    MPI_Finalized(&done);
    if (!done) MPI_Finalize();
  }
#endif
}

void Comm::abort(int code) const {
#ifdef SHATTER_HAVE_MPI
  if (g_initialised && size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

double Comm::max(double v) const {
  max(std::span<double>(&v, 1));
  return v;
}

double Comm::min(double v) const {
#ifdef SHATTER_HAVE_MPI
  if (size_ > 1) allreduce_in_place(&v, 1, MPI_DOUBLE, MPI_MIN);
#endif
  return v;
}

std::int64_t Comm::sum(std::int64_t v) const {
  sum(std::span<std::int64_t>(&v, 1));
  return v;
}

void Comm::sum(std::span<std::int64_t> v) const {
#ifdef SHATTER_HAVE_MPI
  if (size_ > 1) allreduce_in_place(v.data(), v.size(), MPI_INT64_T, MPI_SUM);
#else
  (void)v;
#endif
}

void Comm::max(std::span<double> v) const {
#ifdef SHATTER_HAVE_MPI
  if (size_ > 1) allreduce_in_place(v.data(), v.size(), MPI_DOUBLE, MPI_MAX);
#else
  (void)v;
#endif
}

std::vector<std::int64_t> Comm::allgather(std::span<const std::int64_t> mine) const {
  if (size_ == 1) return {mine.begin(), mine.end()};
#ifdef SHATTER_HAVE_MPI
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(counts.size());
  const int n = as_int(mine.size());
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    displs[r] = as_int(total);
    total += static_cast<std::size_t>(counts[r]);
  }
  std::vector<std::int64_t> all(total);
  MPI_Allgatherv(mine.data(), n, MPI_INT64_T, all.data(), counts.data(), displs.data(), MPI_INT64_T,
                 MPI_COMM_WORLD);
  return all;
#else
  return {};
#endif
}

std::vector<Bytes> Comm::exchange(const std::vector<Bytes>& send, Traffic* traffic) const {
  (void)traffic;
  std::vector<Bytes> recv(static_cast<std::size_t>(size_));
  if (size_ == 1) {
    recv[0] = send[0];
    return recv;
  }
#ifdef SHATTER_HAVE_MPI
  const auto P = static_cast<std::size_t>(size_);
  std::vector<long long> out(P), in(P);
  for (std::size_t r = 0; r < P; ++r) out[r] = static_cast<long long>(send[r].size());
  {
    Timer timer{traffic};  // the count exchange; exchange_known times the messages
    MPI_Alltoall(out.data(), 1, MPI_LONG_LONG, in.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD);
  }
  for (std::size_t r = 0; r < P; ++r) recv[r].resize(static_cast<std::size_t>(in[r]));
  exchange_known(send, recv, traffic);
#endif
  return recv;
}

void Comm::exchange_known(const std::vector<Bytes>& send, std::vector<Bytes>& recv,
                          Traffic* traffic) const {
  const auto P = static_cast<std::size_t>(size_);
  if (size_ == 1) {
    recv[0] = send[0];
    return;
  }
#ifdef SHATTER_HAVE_MPI
  Timer timer{traffic};
  std::vector<MPI_Request> req;
  req.reserve(2 * P);
  constexpr int kTag = 15;
  for (std::size_t r = 0; r < P; ++r) {
    if (recv[r].empty() || static_cast<int>(r) == rank_) continue;
    req.emplace_back();
    MPI_Irecv(recv[r].data(), as_int(recv[r].size()), MPI_BYTE, static_cast<int>(r), kTag,
              MPI_COMM_WORLD, &req.back());
  }
  for (std::size_t r = 0; r < P; ++r) {
    if (send[r].empty() || static_cast<int>(r) == rank_) continue;
    req.emplace_back();
    MPI_Isend(send[r].data(), as_int(send[r].size()), MPI_BYTE, static_cast<int>(r), kTag,
              MPI_COMM_WORLD, &req.back());
    if (traffic) {
      traffic->bytes += send[r].size();
      ++traffic->messages;
    }
  }
  recv[static_cast<std::size_t>(rank_)] = send[static_cast<std::size_t>(rank_)];
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
#else
  (void)send;
  (void)recv;
  (void)traffic;
  (void)P;
#endif
}

std::vector<Bytes> Comm::gather(const Bytes& mine) const {
  if (size_ == 1) return {mine};
  std::vector<Bytes> all;
#ifdef SHATTER_HAVE_MPI
  const auto P = static_cast<std::size_t>(size_);
  long long n = static_cast<long long>(mine.size());
  std::vector<long long> counts(P);
  MPI_Gather(&n, 1, MPI_LONG_LONG, counts.data(), 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  std::vector<Bytes> send(P), recv(P);
  if (rank_ == 0) {
    for (std::size_t r = 0; r < P; ++r) recv[r].resize(static_cast<std::size_t>(counts[r]));
  } else {
    send[0] = mine;
  }
  if (rank_ == 0) send[0] = mine;
  exchange_known(send, recv, nullptr);
  if (rank_ == 0) all = std::move(recv);
#endif
  return all;
}

void Comm::broadcast(Bytes& data, int root) const {
#ifdef SHATTER_HAVE_MPI
  if (size_ == 1) return;
  long long n = static_cast<long long>(data.size());
  MPI_Bcast(&n, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD);
  data.resize(static_cast<std::size_t>(n));
  MPI_Bcast(data.data(), as_int(data.size()), MPI_BYTE, root, MPI_COMM_WORLD);
#else
  (void)data;
  (void)root;
#endif
}

void Comm::barrier() const {
#ifdef SHATTER_HAVE_MPI
  if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

}  // namespace shatter::parallel
