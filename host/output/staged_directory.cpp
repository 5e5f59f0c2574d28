#include "host/output/staged_directory.hpp"

#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "host/output/interrupt_cleanup.hpp"
#include "sim/error.hpp"

namespace rheo::output {

namespace fs = std::filesystem;

namespace {

bool is_empty_directory(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec) && fs::is_empty(p, ec);
}

// Sibling names are ".TARGET.TAG-PID-XXXXXX": the PID of the run that made it, so a later
// run can tell a live run's staging directory from one left by a killed run (kill -9 or a
// power cut give the owner no chance to remove it).
std::string sibling_prefix(const fs::path& target, const std::string& tag) {
  // Built with append() rather than operator+ chains, which trip GCC 12's -Wrestrict.
  std::string name(".");
  name.append(target.filename().string()).append(".").append(tag).append("-");
  return name;
}

// A unique sibling name from a mkdtemp(3) template (so two runs never share one).
std::string make_sibling(const fs::path& target, const std::string& tag) {
  std::string name = sibling_prefix(target, tag);
  name.append(std::to_string(getpid())).append("-XXXXXX");
  const std::string templ = (target.parent_path() / name).string();
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) {
    throw Error(templ + ": cannot create a temporary directory next to the output: " +
                std::strerror(errno));
  }
  return std::string(buf.data());
}

// Every staging directory holds this file while a run owns it (taken out just before the
// results move into place): a leftover is removed only when it carries it (or is empty), so
// a directory of the user's that merely has a staging-like name is never touched.
constexpr const char* kStagingMarker = ".rheo-staging";

void mark_as_staging(const fs::path& dir) {
  std::FILE* f = std::fopen((dir / kStagingMarker).c_str(), "w");
  if (f) std::fclose(f);
}

// True when `p` is `dir` or lies below it, compared both as written and as the file system
// resolves them (symbolic links followed, then ".."), so that neither a link to an input, an
// --out that is a link, nor a ".." after a link hides an input from the check.
bool within(const fs::path& p, const fs::path& dir) {
  const auto below = [](const fs::path& a, const fs::path& b) {
    const fs::path rel = a.lexically_relative(b);
    return !rel.empty() && *rel.begin() != "..";
  };
  std::error_code e1, e2;
  const fs::path rp = fs::weakly_canonical(p, e1);
  const fs::path rd = fs::weakly_canonical(dir, e2);
  const fs::path lp = p.lexically_normal(), ld = dir.lexically_normal();
  return below(lp, ld) || (!e1 && !e2 && below(rp, rd)) || (!e1 && below(rp, ld)) ||
         (!e2 && below(lp, rd));
}

// Removes staging directories of `target` whose run no longer exists, and says so: only
// real directories (not links) that carry the staging marker or are empty, and never one
// that holds an input of the command.
void remove_leftovers(const fs::path& target, const std::vector<std::string>& inputs) {
  std::error_code ec;
  for (const char* tag : {"partial", "old"}) {
    const std::string prefix = sibling_prefix(target, tag);
    for (const auto& entry : fs::directory_iterator(target.parent_path(), ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind(prefix, 0) != 0) continue;
      const std::string rest = name.substr(prefix.size());
      const std::size_t dash = rest.find('-');
      if (dash == std::string::npos || dash == 0) continue;  // not one of ours
      pid_t pid = 0;
      try {
        pid = static_cast<pid_t>(std::stol(rest.substr(0, dash)));
      } catch (const std::exception&) {
        continue;
      }
      if (pid <= 0 || kill(pid, 0) == 0 || errno != ESRCH) continue;  // its run still exists
      std::error_code st;
      if (!fs::is_directory(fs::symlink_status(entry.path(), st))) continue;
      if (!fs::is_regular_file(entry.path() / kStagingMarker, st) &&
          !is_empty_directory(entry.path())) {
        continue;  // not made by a run of rheo: the user's own
      }
      bool holds_input = false;
      for (const std::string& input : inputs) {
        holds_input = holds_input || within(fs::absolute(fs::path(input)), entry.path());
      }
      if (holds_input) continue;
      std::error_code rm;
      fs::remove_all(entry.path(), rm);
      if (!rm) {
        std::cerr << "rheo: note: removed " << entry.path().string()
                  << ", left by an interrupted run (process " << pid << " no longer exists)\n";
      }
    }
  }
}

// `p` absolute, without a trailing separator, and naming what the kernel would open: its
// directories resolved as the file system does (a ".." after a symbolic link goes up from the
// link's target, not from the link), its last component kept as written (a link given as
// --out stays that link) unless it is "." or "..".
fs::path absolute_path(const std::string& p) {
  const fs::path a = fs::absolute(fs::path(p));
  fs::path last = a.filename();
  fs::path dir = a.parent_path();
  std::error_code ec;
  if (last.empty() || last == "." || last == "..") {
    fs::path whole = fs::weakly_canonical(a, ec);
    if (ec) whole = a.lexically_normal();
    if (!whole.has_filename() && whole.has_parent_path() && whole != whole.root_path()) {
      whole = whole.parent_path();
    }
    return whole;
  }
  fs::path resolved = fs::weakly_canonical(dir, ec);
  if (ec) resolved = dir.lexically_normal();
  return resolved / last;
}

// Refuses to replace `target` (a directory, or a file's final path) when that would delete
// what the command reads.
void refuse_replacing_inputs(const fs::path& target, const std::vector<std::string>& inputs,
                             const std::string& option) {
  for (const std::string& input : inputs) {
    if (within(absolute_path(input), target) || within(fs::absolute(fs::path(input)), target)) {
      const bool file = option != "--out";
      throw Error((file ? "the output file " : option + " ") + target.string() +
                  (file ? ": is " : ": holds ") + input +
                  ", which this command reads; replacing it (--force) would delete the input. "
                  "Choose another " + (file ? std::string("file name") : option) +
                  (file ? "" : " or move the input out of it"));
    }
  }
}

}  // namespace

StagedDirectory::StagedDirectory(const std::string& target, bool replace,
                                 const std::vector<std::string>& inputs)
    : replace_(replace), inputs_(inputs) {
  const fs::path t = absolute_path(target);
  target_ = t.string();
  if (t == t.root_path()) throw Error("--out " + target_ + ": the file system's root is not an output directory");
  std::error_code ec;
  // A link that points nowhere: refused now, not after the whole run when the results
  // cannot be moved into place.
  if (fs::is_symlink(fs::symlink_status(t, ec)) && !fs::exists(t, ec)) {
    throw Error("--out " + target_ + ": is a symbolic link to " +
                fs::read_symlink(t, ec).string() +
                ", which does not exist; create that directory or choose another --out");
  }
  if (fs::exists(t, ec)) {
    if (!fs::is_directory(t, ec)) {
      throw Error(target_ + ": exists and is not a directory (choose another --out)");
    }
    if (!is_empty_directory(t)) {
      if (!replace_) {
        throw Error(target_ +
                    ": output directory exists and is not empty; choose another --out or pass "
                    "--force to replace its content");
      }
      // Replacing it deletes everything in it: never the inputs, never the directory the
      // command (and the shell that started it) works in.
      refuse_replacing_inputs(t, inputs_, "--out");
      if (within(fs::current_path(ec), t)) {
        throw Error("--out " + target_ +
                    ": is the working directory or holds it; replacing it (--force) would "
                    "delete everything in it. Choose a new directory for the results");
      }
    }
  }
  fs::create_directories(t.parent_path(), ec);
  if (ec) throw Error(t.parent_path().string() + ": cannot create directory: " + ec.message());
  remove_leftovers(t, inputs_);
  staging_ = make_sibling(t, "partial");
  mark_as_staging(staging_);
  register_interrupt_cleanup(staging_, "staged results for " + target_);
  // mkdtemp makes the directory private (0700); results are ordinary files (0755 dirs).
  fs::permissions(staging_,
                  fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                      fs::perms::others_read | fs::perms::others_exec,
                  ec);
}

StagedDirectory::~StagedDirectory() {
  if (committed_) return;
  std::error_code ec;
  // Best effort: a destructor must not throw.
  for (const StagedFile& f : files_) {
    fs::remove_all(f.staging_dir, ec);
    unregister_interrupt_cleanup(f.staging_dir);
  }
  fs::remove_all(staging_, ec);
  unregister_interrupt_cleanup(staging_);
}

std::string StagedDirectory::map(const std::string& user_path) const {
  const fs::path p = absolute_path(user_path);
  const fs::path rel = p.lexically_relative(target_);
  if (rel.empty() || *rel.begin() == "..") return user_path;
  return (fs::path(staging_) / rel).string();
}

std::string StagedDirectory::stage_file(const std::string& user_path,
                                        const std::vector<std::string>& companions) {
  const std::string inside = map(user_path);
  if (inside != user_path) return inside;
  StagedFile f;
  std::vector<std::string> paths{user_path};
  paths.insert(paths.end(), companions.begin(), companions.end());
  const fs::path dir = absolute_path(user_path).parent_path();
  for (const std::string& p : paths) {
    const fs::path a = absolute_path(p);
    if (a.parent_path() != dir)
      throw Error(p + ": a companion file must lie beside " + user_path);
    std::error_code ec;
    if (fs::exists(a, ec)) {
      if (fs::is_directory(a, ec)) throw Error(p + ": exists and is a directory");
      // --force replaces an earlier output, never a device, a pipe or a socket (as root,
      // --trace /dev/null --force would have replaced the system's /dev/null).
      if (!fs::is_regular_file(a, ec)) {
        throw Error(p + ": exists and is not a regular file (a device, pipe or socket); " +
                    "choose a file name");
      }
      if (!replace_)
        throw Error(p + ": exists; choose another file name or pass --force to replace it");
      refuse_replacing_inputs(a, inputs_, "file");
    }
    f.finals.push_back(a.string());
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(dir.string() + ": cannot create directory: " + ec.message());
  const fs::path first(f.finals.front());
  remove_leftovers(first, inputs_);
  f.staging_dir = make_sibling(first, "partial");
  mark_as_staging(f.staging_dir);
  register_interrupt_cleanup(f.staging_dir, "staged " + f.finals.front());
  files_.push_back(f);
  return (fs::path(f.staging_dir) / first.filename()).string();
}

void StagedDirectory::commit() {
  // An interrupt waits until the results are in place (or the attempt failed).
  std::lock_guard<std::mutex> lock(interrupt_cleanup_mutex());
  const fs::path target(target_);
  std::error_code ec;
  // The results go into place without the marker (a failed move leaves it out, so the
  // directory then stays for the user rather than being taken as a leftover).
  fs::remove(fs::path(staging_) / kStagingMarker, ec);
  if (fs::exists(target, ec) && !is_empty_directory(target)) {
    if (!replace_) throw Error(target_ + ": appeared during the run and is not empty");
    // Move the old content aside first, so that the target is never half old, half new.
    const std::string old = make_sibling(target, "old");
    fs::remove(old, ec);
    fs::rename(target, old, ec);
    if (ec) throw Error(target_ + ": cannot move the old output aside: " + ec.message());
    mark_as_staging(old);  // being replaced: a leftover of it may go
    fs::rename(staging_, target, ec);
    if (ec) {
      std::error_code undo;
      fs::rename(old, target, undo);
      throw Error(target_ + ": cannot move the results into place: " + ec.message());
    }
    fs::remove_all(old, ec);
  } else {
    // rename(2) replaces an empty directory atomically.
    fs::rename(staging_, target, ec);
    if (ec) throw Error(target_ + ": cannot move the results into place: " + ec.message());
  }
  committed_ = true;
  for (const StagedFile& f : files_) {
    for (const std::string& final_path : f.finals) {
      const fs::path staged = fs::path(f.staging_dir) / fs::path(final_path).filename();
      if (!fs::exists(staged, ec)) continue;  // a companion the run did not write
      if (fs::exists(final_path, ec) && !replace_)
        throw Error(final_path + ": appeared during the run; the new one is in " + f.staging_dir);
      fs::rename(staged, final_path, ec);
      if (ec)
        throw Error(final_path + ": cannot move into place: " + ec.message() + " (it is in " +
                    f.staging_dir + ")");
    }
    fs::remove_all(f.staging_dir, ec);
  }
  // Unregistered only now: the lock is still held, so no interrupt can see a half state.
  for (const StagedFile& f : files_) unregister_interrupt_cleanup_locked(f.staging_dir);
  unregister_interrupt_cleanup_locked(staging_);
}

}  // namespace rheo::output
