#include "granpack/comm/shared_window.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <exception>

#include "granpack/core/error.h"

namespace granpack {

namespace {
/// Slots start on their own 64-byte cache line: a writer filling one slot does not invalidate
/// the line a reader is loading from another.
constexpr std::size_t kLine = 64 / sizeof(double);

std::size_t round_up(std::size_t n) {
  return (n + kLine - 1) / kLine * kLine;
}
} // namespace

bool ranks_share_one_node(MPI_Comm comm) {
  int size = 0, node_size = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &node_size);
  MPI_Comm_free(&node);
  // Node communicators partition comm: if one rank's is all of comm, every rank's is.
  return node_size == size;
}

unsigned long long file_size_limit() {
  rlimit r{};
  if (getrlimit(RLIMIT_FSIZE, &r) != 0 || r.rlim_cur == RLIM_INFINITY)
    return 0;
  return static_cast<unsigned long long>(r.rlim_cur);
}

SharedWindow::SharedWindow(MPI_Comm comm) {
  MPI_Comm_dup(comm, &comm_);
  MPI_Comm_rank(comm_, &rank_);
  on_one_node_ = ranks_share_one_node(comm_);
}

SharedWindow::~SharedWindow() {
  // A SharedWindow that outlived MPI (it must not: its owners live inside main's MPI scope)
  // cannot free anything any more; say nothing and leave it to the process's end.
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized)
    return;
  // Destroyed while an exception unwinds: the error is either collective (every rank unwinds
  // and skips the free alike) or known to this rank alone, on its way to main's MPI_Abort,
  // while the other ranks wait elsewhere; the collective free would then wait for them
  // forever instead of letting the job abort. So the window and its communicator are left to
  // MPI_Finalize (Open MPI 4.1 finalizes cleanly with a locked shared window still open) or to
  // the abort. The price: a leaked window per Halo alive at a collective error.
  if (std::uncaught_exceptions() > 0)
    return;
  release();
  MPI_Comm_free(&comm_);
}

bool SharedWindow::serves(MPI_Comm comm) const {
  int result = MPI_UNEQUAL;
  MPI_Comm_compare(comm_, comm, &result);
  return result == MPI_IDENT || result == MPI_CONGRUENT;
}

void SharedWindow::release() {
  if (win_ == MPI_WIN_NULL)
    return;
  MPI_Win_unlock_all(win_);
  // No rank may unmap the segments while another still reads them. MPI_Win_free synchronises
  // like a barrier (the standard's advice to implementors, which Open MPI's osc/sm follows);
  // the explicit barrier makes that independent of the implementation, at the cost of one
  // barrier per reallocation.
  MPI_Barrier(comm_);
  MPI_Win_free(&win_);
  base_.clear();
}

bool SharedWindow::reserve(const std::vector<std::size_t>& need) {
  GRANPACK_CHECK(on_one_node_, "SharedWindow::reserve: the ranks do not share one node");
  if (!usable_)
    return false;
  std::vector<unsigned long long> most(need.begin(), need.end());
  MPI_Allreduce(MPI_IN_PLACE, most.data(), static_cast<int>(most.size()), MPI_UNSIGNED_LONG_LONG,
                MPI_MAX, comm_);
  // The same answer on every rank (from the all-reduced needs): all reallocate or none.
  bool enough = allocated() && room_.size() == most.size();
  for (std::size_t k = 0; enough && k < most.size(); ++k)
    enough = most[k] <= room_[k];
  if (enough)
    return false;

  release();
  room_.resize(most.size(), 0);
  offset_.assign(most.size(), 0);
  std::size_t total = 0;
  for (std::size_t k = 0; k < most.size(); ++k) {
    // Never smaller than before (a need that shrinks and grows again does not reallocate), at
    // least one cache line (no slot of a writer shares a line with another), 1.5x the need.
    const auto m = static_cast<std::size_t>(most[k]);
    room_[k] = round_up(std::max({room_[k], kLine, m + m / 2}));
    offset_[k] = total;
    total += room_[k];
  }
  // Open MPI's osc/sm backs the window with one file: every rank's segment rounded up to a
  // page, plus its synchronisation state (well under a page per rank) and a global header. If
  // that file would pass some rank's file size limit (ulimit -f), MPI_Win_allocate_shared
  // fails inside Open MPI and the job aborts; so the window is given up first, on every rank
  // alike (the all-reduce), and the halo carries on through messages. A generous bound (two
  // pages per rank and 1 MiB more) errs towards messages, never towards an abort.
  int size = 0;
  MPI_Comm_size(comm_, &size);
  const auto page = static_cast<unsigned long long>(sysconf(_SC_PAGESIZE));
  const unsigned long long segment = (total * sizeof(double) + page - 1) / page * page;
  const unsigned long long file_bytes =
      static_cast<unsigned long long>(size) * (segment + 2 * page) + (1ULL << 20);
  const unsigned long long limit = file_size_limit();
  int fits = limit == 0 || file_bytes <= limit ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &fits, 1, MPI_INT, MPI_MIN, comm_);
  if (!fits) {
    usable_ = false;
    room_.clear();
    offset_.clear();
    return false;
  }
  MPI_Info info;
  MPI_Info_create(&info);
  // Each rank's segment on its own pages (first touched by its writer: on a NUMA node, in the
  // writer's memory); the layout is the same either way, since base_ comes from the query.
  MPI_Info_set(info, "alloc_shared_noncontig", "true");
  double* my_base = nullptr;
  MPI_Win_allocate_shared(static_cast<MPI_Aint>(total * sizeof(double)),
                          static_cast<int>(sizeof(double)), info, comm_, &my_base, &win_);
  MPI_Info_free(&info);
  base_.assign(static_cast<std::size_t>(size), nullptr);
  for (int r = 0; r < size; ++r) {
    MPI_Aint bytes = 0;
    int disp_unit = 0;
    MPI_Win_shared_query(win_, r, &bytes, &disp_unit, &base_[static_cast<std::size_t>(r)]);
  }
  MPI_Win_lock_all(MPI_MODE_NOCHECK, win_);
  ++allocations_;
  return true;
}

void SharedWindow::notify(const int (&to)[2], const int (&from)[2], int tag) const {
  MPI_Win_sync(win_);
  MPI_Request req[4];
  for (int q = 0; q < 2; ++q)
    MPI_Irecv(nullptr, 0, MPI_BYTE, from[q], tag + q, comm_, &req[q]);
  for (int q = 0; q < 2; ++q)
    MPI_Isend(nullptr, 0, MPI_BYTE, to[q], tag + q, comm_, &req[2 + q]);
  MPI_Waitall(4, req, MPI_STATUSES_IGNORE);
  MPI_Win_sync(win_);
}

} // namespace granpack
