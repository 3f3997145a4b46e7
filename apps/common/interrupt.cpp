#include "interrupt.hpp"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "splitgrid/formats/temporary_paths.hpp"

#include <spdlog/spdlog.h>

namespace sg::apps {
namespace {

/// Who got there first: the work (finish()) or an interrupt. Decided by one compare and
/// exchange, so exactly one of them acts.
enum RunState : int { running = 0, finished = 1, interrupted = 2 };
std::atomic<int> run_state{running};

sigset_t interrupt_signals()
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    return set;
}

// Set by the interrupt thread once it has started (its thread-local storage and the
// sanitizers' per-thread state allocated) and is about to wait; see InterruptHandling().
std::atomic<bool> interrupt_thread_ready{false};

void wait_for_interrupt()
{
    const sigset_t set = interrupt_signals();
    int signal_number = 0;
    interrupt_thread_ready.store(true);
    interrupt_thread_ready.notify_all();
    while (sigwait(&set, &signal_number) != 0) {
    }
    int expected = running;
    if (!run_state.compare_exchange_strong(expected, interrupted)) return;  // already done
    run_interrupt_cleanup();
    spdlog::error("interrupted");
    spdlog::default_logger()->flush();
    ::_exit(128 + signal_number);
}

}  // namespace

InterruptHandling::InterruptHandling()
{
    const sigset_t set = interrupt_signals();
    if (const int error = pthread_sigmask(SIG_BLOCK, &set, nullptr); error != 0)
        throw std::system_error(error, std::generic_category(), "pthread_sigmask");
    std::thread(wait_for_interrupt).detach();
    // The mesh import forks a child (formats/src/import_child.cpp). A thread that is still
    // starting may hold an allocator lock at that moment, which the child then inherits locked
    // forever (seen with AddressSanitizer's allocator, whose fork handling in GCC 12 does not
    // take its locks): so the tool goes on only once the thread is up and only waits.
    interrupt_thread_ready.wait(false);
}

void InterruptHandling::finish()
{
    int expected = running;
    if (run_state.compare_exchange_strong(expected, finished)) return;
    // The interrupt thread is cleaning up and ends the process; nothing may be reported.
    for (;;) ::pause();
}

}  // namespace sg::apps
