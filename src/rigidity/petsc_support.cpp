#include "granpack/rigidity/petsc_support.h"

#include <slepcsys.h>

#include <sstream>

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
}  // namespace detail

void ensure_petsc_initialized() {
  PetscBool done = PETSC_FALSE;
  SlepcInitialized(&done);
  if (done) return;
  // No command-line arguments: granpack's own CLI owns argv. Solver options can still be
  // given through the PETSC_OPTIONS environment variable (prefix "stiffness_").
  GRANPACK_PETSC(SlepcInitializeNoArguments());
}

void finalize_petsc() {
  PetscBool done = PETSC_FALSE;
  SlepcInitialized(&done);
  if (done) SlepcFinalize();
}

}  // namespace granpack
