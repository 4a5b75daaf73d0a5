#include "granpack/rigidity/petsc_support.h"

#include <dlfcn.h>
#include <mpi.h>
#include <slepcsys.h>

#include <cstdlib>
#include <sstream>

#include "granpack/comm/communicator.h"

namespace granpack {

namespace detail {
void petsc_failed(PetscErrorCode code, const char* call, const char* file, int line) {
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  std::ostringstream os;
  os << "PETSc/SLEPc call failed: " << call << " (error " << code << ": "
     << (text ? text : "unknown") << ") at " << file << ":" << line;
  throw Error(os.str());
}
} // namespace detail

namespace {
/// MUMPS's dense fronts go to whichever BLAS libblas.so.3 points to. OpenBLAS (Debian's
/// libopenblas0-pthread, 10-100x faster than the reference BLAS on these factorisations)
/// starts one thread per core in every process: with several ranks on a node they fight for
/// the cores. Unless the user chose (OPENBLAS_NUM_THREADS), one thread per rank when there
/// are several ranks. Looked up at run time: nothing to do with another BLAS.
void limit_blas_threads() {
  if (std::getenv("OPENBLAS_NUM_THREADS") || std::getenv("OMP_NUM_THREADS"))
    return;
  const int size = size_of(MPI_COMM_WORLD);
  if (size == 1)
    return;
  using SetThreads = void (*)(int);
  if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
    set(1);
}
} // namespace

void ensure_petsc_initialized() {
  PetscBool done = PETSC_FALSE;
  SlepcInitialized(&done);
  if (done)
    return;
  limit_blas_threads();
  // No command-line arguments: granpack's own CLI owns argv. Solver options can still be
  // given through the PETSC_OPTIONS environment variable (prefix "stiffness_").
  GRANPACK_PETSC(SlepcInitializeNoArguments());
}

void finalize_petsc() {
  PetscBool done = PETSC_FALSE;
  SlepcInitialized(&done);
  if (done)
    SlepcFinalize();
}

} // namespace granpack
