#pragma once
// PETSc error checking and start-up shared by the CD0 PETSc backend and its options check.
#include <petscsys.h>

#include <string>

namespace jamsim::linalg::petsc {

/// PETSc's text for an error code and its last detailed message.
std::string error_text(PetscErrorCode rc);

/// Every PETSc call goes through here: a non-zero code becomes a std::runtime_error naming the
/// call (PETSc's own handler is replaced by PetscReturnErrorHandler, so nothing aborts the job).
inline void check(PetscErrorCode rc, const char* what) {
    if (rc != 0) throw std::runtime_error(std::string("PETSc: ") + what + " failed: " + error_text(rc));
}

/// Initialises PETSc on first use, on this process alone (each rank solves its own replicas).
void ensure_initialized();

}  // namespace jamsim::linalg::petsc
