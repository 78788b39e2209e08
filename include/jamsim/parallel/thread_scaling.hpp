#pragma once
// Which of the kernel's parts a replica's time goes to, as far as threads are concerned: what
// a model declares in its registration so that the scheduler and the core lending
// (campaign/scheduler.hpp) give it no more threads than it can use.

namespace jamsim {

/// How a replica's kernel gains from threads (the measured tables: SpeedupModel).
enum class ThreadScaling {
    /// Pair forces, integration, samples: RD0, RD0T and the massive models (SLLOD).
    pair_loop,
    /// Energy minimisation (CG, FIRE): QS and the jamming protocols.
    minimiser,
    /// A pair loop plus the CD0 contact matrix's factor update and solve each step, which
    /// run mostly on one thread.
    contact_solve,
};

}  // namespace jamsim
