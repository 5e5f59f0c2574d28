// What an interrupted command leaves behind: nothing. SIGINT, SIGTERM and SIGHUP end a
// command that writes results by removing every path registered here (the staged output
// directories and staged files of output::StagedDirectory), saying so on stderr, and
// exiting with 128 + the signal's number (130, 143, 129), as a shell reports a command
// killed by that signal.
//
// The handler itself only writes the signal's number into a pipe (the one thing a handler
// may safely do); a watcher thread reads it and does the removal in ordinary code, under
// the same lock that StagedDirectory::commit() takes, so that a signal never lands between
// the two renames of a commit. Nothing is blocked or masked, so child processes (Yosys,
// gnuplot) get the signal as they would without rheo.
#pragma once

#include <mutex>
#include <string>

namespace rheo::output {

// Installs the handlers and starts the watcher the first time it is called.
void install_interrupt_cleanup();

// Registers a path to remove (recursively) if the command is interrupted; `what` says what
// it was, for the message. unregister...() is called once the path is committed or gone.
void register_interrupt_cleanup(const std::string& path, const std::string& what);
void unregister_interrupt_cleanup(const std::string& path);
// The same, for a caller that holds interrupt_cleanup_mutex().
void unregister_interrupt_cleanup_locked(const std::string& path);

// The lock that the watcher takes before removing anything: hold it while moving staged
// results into place.
std::mutex& interrupt_cleanup_mutex();

}  // namespace rheo::output
