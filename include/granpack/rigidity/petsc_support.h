#pragma once
// PETSc/SLEPc support for the rigidity layer: every call checked (a non-zero code becomes a
// granpack::Error carrying the call's text and PETSc's message), owning handles for the
// objects, and the library initialisation.
//
// Collectiveness: the PETSc calls wrapped here are collective on the objects' communicator
// and fail on every rank together for the errors this layer can meet (bad sizes, out of
// memory in a factorisation is reported by MUMPS on all ranks through INFOG(1)).
#include <petscksp.h>
#include <petscmat.h>
#include <petscvec.h>

#include <utility>

#include "granpack/core/error.h"

namespace granpack {

namespace detail {
[[noreturn]] void petsc_failed(PetscErrorCode code, const char* call, const char* file, int line);
} // namespace detail

/// Starts SLEPc (and PETSc) once per process if nobody did; never finalises (PETSc cannot be
/// restarted): the executable calls finalize_petsc() before MPI_Finalize.
void ensure_petsc_initialized();
void finalize_petsc();

/// An owning handle: destroys the PETSc object when it goes out of scope.
template <class T, PetscErrorCode (*destroy)(T*)> class PetscHandle {
public:
  PetscHandle() = default;
  explicit PetscHandle(T h) : h_(h) {}
  PetscHandle(const PetscHandle&) = delete;
  PetscHandle& operator=(const PetscHandle&) = delete;
  PetscHandle(PetscHandle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  PetscHandle& operator=(PetscHandle&& o) noexcept {
    reset();
    h_ = std::exchange(o.h_, nullptr);
    return *this;
  }
  ~PetscHandle() { reset(); }
  void reset() {
    if (h_)
      destroy(&h_);
    h_ = nullptr;
  }
  T* address() { return &h_; }
  operator T() const { return h_; }
  T get() const { return h_; }

private:
  T h_ = nullptr;
};

using OwnedMat = PetscHandle<Mat, MatDestroy>;
using OwnedVec = PetscHandle<::Vec, VecDestroy>;
using OwnedKsp = PetscHandle<KSP, KSPDestroy>;
using OwnedNullSpace = PetscHandle<MatNullSpace, MatNullSpaceDestroy>;

} // namespace granpack

/// Checks a PETSc call: throws granpack::Error naming the call when it fails.
#define GRANPACK_PETSC(call)                                                                       \
  do {                                                                                             \
    const PetscErrorCode granpack_petsc_code_ = (call);                                            \
    if (granpack_petsc_code_ != 0)                                                                 \
      ::granpack::detail::petsc_failed(granpack_petsc_code_, #call, __FILE__, __LINE__);           \
  } while (0)
