#pragma once
// An MPI-3 shared-memory window over ranks that share one node, cut into slots of doubles that
// a rank writes and its neighbours read in place (the halo's shared-memory path, comm/halo.h):
// the copy an MPI transport makes of a message disappears.
//
// Every rank's segment has the same layout (slot k at the same offset with the same room, the
// largest any rank needs), so a reader finds slot k of any writer's segment without asking it.
// The window is locked (MPI_Win_lock_all, MPI_MODE_NOCHECK) for its whole life: ranks load and
// store directly and order themselves with zero-byte messages and MPI_Win_sync (notify()), the
// "shared memory + point-to-point synchronisation" pattern of the MPI-3 standard (sec. 11.8).
#include <mpi.h>

#include <cstddef>
#include <vector>

namespace granpack {

/// Collective on comm: true when every rank of comm shares one node with every other
/// (MPI_Comm_split_type(MPI_COMM_TYPE_SHARED) gives them all one communicator).
bool ranks_share_one_node(MPI_Comm comm);

/// The soft file size limit of this process (ulimit -f, RLIMIT_FSIZE) in bytes, or 0 when
/// there is none. Open MPI backs a shared window with a file: one larger than the limit makes
/// MPI_Win_allocate_shared fail and abort the job, so the window is not allocated then.
unsigned long long file_size_limit();

class SharedWindow {
public:
  /// Collective on comm. Duplicates it: the window and its notifications use the duplicate,
  /// so notifications can never be matched by another receive of the program. Allocates
  /// nothing yet (reserve()).
  explicit SharedWindow(MPI_Comm comm);
  /// Collective on the communicator (frees the window and the duplicate): every rank must
  /// destroy its SharedWindow, as every rank destroys the Halo holding it. Destroyed while an
  /// exception unwinds, it frees nothing (not collective: shared_window.cpp says why).
  ~SharedWindow();
  SharedWindow(const SharedWindow&) = delete;
  SharedWindow& operator=(const SharedWindow&) = delete;

  /// Whether all ranks share one node (ranks_share_one_node): only then may reserve() be called.
  bool on_one_node() const { return on_one_node_; }
  /// Whether this window serves `comm`: the same ranks in the same order (MPI_Comm_compare
  /// ident or congruent), so that rank r of comm writes segment r. Local.
  bool serves(MPI_Comm comm) const;
  /// Collective: makes room for need[k] doubles in slot k on every rank (the largest need over
  /// the ranks; need.size() the same everywhere). Reallocates (with half as much again as
  /// headroom, so that a growing need does not reallocate at every call) only when some rank
  /// needs more room than the window has; otherwise it costs one small all-reduce and
  /// allocates nothing. Reallocation discards the contents. Returns true when it reallocated.
  /// When the new window's backing file would exceed some rank's file size limit
  /// (file_size_limit()), it allocates nothing, frees the old window and marks the window
  /// unusable (usable() false, decided alike on every rank): the halo then uses messages.
  bool reserve(const std::vector<std::size_t>& need);
  /// False once reserve() found that no window fits the file size limit; reserve() then does
  /// nothing (and allocated() stays false) for the rest of this window's life.
  bool usable() const { return usable_; }
  /// Whether reserve() has allocated the window.
  bool allocated() const { return win_ != MPI_WIN_NULL; }
  /// How many times reserve() has (re)allocated the window.
  int allocations() const { return allocations_; }
  /// Slot k of this rank's segment, to write.
  double* mine(std::size_t slot) const { return base_[rank_] + offset_[slot]; }
  /// Slot k of `rank`'s segment, to read (after a notification from `rank`).
  const double* of(int rank, std::size_t slot) const { return base_[rank] + offset_[slot]; }
  /// The writer/reader handshake of one exchange: this rank has written its slots for ranks
  /// to[q] and reads the slots ranks from[q] wrote for it. Sends a zero-byte message with tag
  /// tag + q to each to[q], waits for the one from each from[q], and syncs the window before
  /// (our stores are visible before a reader can know of them) and after (the writers' stores
  /// are visible to our loads, and our earlier loads are done before our next stores). Ranks
  /// may repeat (to[0] == to[1]); the tags keep the pairs apart.
  void notify(const int (&to)[2], const int (&from)[2], int tag) const;

private:
  void release();

  MPI_Comm comm_ = MPI_COMM_NULL;
  MPI_Win win_ = MPI_WIN_NULL;
  int rank_ = 0;
  bool on_one_node_ = false;
  bool usable_ = true;
  int allocations_ = 0;
  std::vector<std::size_t> offset_, room_; ///< per slot, in doubles (the same on every rank)
  std::vector<double*> base_;              ///< every rank's segment, mapped into ours
};

} // namespace granpack
