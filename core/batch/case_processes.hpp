// Runs a sweep's cases each in its own forked process, so a case that crashes (a
// segfault, an abort, a CPU-time limit) is recorded as failed and the others finish.
//
//   parent (one thread):  fork a worker per case, at most `workers` at once
//   worker:               runSweepCase (the same function as the thread pool, so the
//                         results are the same bytes), report over a pipe, _exit
//   parent:               a worker killed by a signal -> "crashed (SIGSEGV)"; a stop
//                         signal (core/sim/stop_signal.hpp) -> no new case starts, the
//                         running ones are told to stop and end "interrupted"
//
// The parent forks only while it has no other thread, so the child inherits no lock
// held by another thread (HDF5's, the allocator's).
#pragma once
#include <functional>
#include <vector>

#include "core/batch/batch_runner.hpp"

namespace packsim {

void runCasesInProcesses(const Sweep& sweep, bool resume, int workers, std::vector<CaseOutcome>& outcomes,
                         const std::function<void(size_t)>& caseDone);

}  // namespace packsim
