#include "petsc_support.hpp"

#include <mpi.h>

namespace jamsim::linalg::petsc {

std::string error_text(PetscErrorCode rc) {
    const char* text = nullptr;
    char* specific = nullptr;
    PetscErrorMessage(rc, &text, &specific);
    std::string out = text ? text : "error";
    if (specific && *specific) out += std::string(" (") + specific + ")";
    return out;
}

void ensure_initialized() {
    PetscBool up = PETSC_FALSE;
    check(PetscInitialized(&up), "PetscInitialized");
    if (up) return;
    // Each rank solves its own replicas and initialises PETSc when it first needs it, at a
    // time no other rank shares: PETSc's world must then be this process alone.
    // (Only when MPI is already running; otherwise PETSc starts it for this process alone.)
    int mpi_up = 0;
    MPI_Initialized(&mpi_up);
    if (mpi_up) PETSC_COMM_WORLD = MPI_COMM_SELF;
    check(PetscOptionsSetValue(nullptr, "-no_signal_handler", "true"), "PetscOptionsSetValue");
    check(PetscInitializeNoArguments(), "PetscInitialize");
    check(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr), "PetscPushErrorHandler");
}

}  // namespace jamsim::linalg::petsc
