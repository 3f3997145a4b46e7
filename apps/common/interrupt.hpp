#pragma once

/// SIGINT and SIGTERM for the tools: the one place where an interrupted run is cleaned up.
///
/// A signal handler may call only async-signal-safe functions, and the work it interrupts
/// (oneTBB workers, VTK writers, the wait for the mesh import's child process) cannot be
/// unwound from one. So no handler is installed: InterruptHandling blocks both signals in
/// the main thread before any other thread exists, so that every thread the tool starts and
/// every child it forks or spawns inherits the block, and one thread of its own takes them
/// with sigwait(). That thread is an ordinary thread: it runs sg::run_interrupt_cleanup()
/// (formats/temporary_paths.hpp: kill the registered child processes, remove the registered
/// temporary files and staging folders), prints the one line "error: interrupted" and ends
/// the process with 128 + the signal number (130 for SIGINT, 143 for SIGTERM), without
/// running exit handlers under the feet of the other threads. An output that was not yet
/// renamed into place is never touched: the rename and the cleanup exclude each other
/// (sg::hold_off_cleanup()). SIGKILL cannot be caught; the next run for the same output
/// removes what it left (sg::remove_stale_temporaries()).
namespace sg::apps {

class InterruptHandling {
public:
    /// Blocks SIGINT and SIGTERM and starts the thread that waits for them. Call before any
    /// other thread is started.
    InterruptHandling();
    InterruptHandling(const InterruptHandling&) = delete;
    InterruptHandling& operator=(const InterruptHandling&) = delete;

    /// Marks the tool's work as finished, before it reports its result or its error. If an
    /// interrupt came first, it never returns (the interrupt thread ends the process, and the
    /// tool must not report an error that the interrupt itself caused, such as a killed
    /// child); an interrupt that comes later is ignored and the tool exits normally.
    void finish();
};

}  // namespace sg::apps
