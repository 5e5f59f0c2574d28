#include "host/output/staged_directory.hpp"

#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

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

// Removes staging directories of `target` whose run no longer exists, and says so.
void remove_leftovers(const fs::path& target) {
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
      std::error_code rm;
      fs::remove_all(entry.path(), rm);
      if (!rm) {
        std::cerr << "rheo: note: removed " << entry.path().string()
                  << ", left by an interrupted run (process " << pid << " no longer exists)\n";
      }
    }
  }
}

}  // namespace

StagedDirectory::StagedDirectory(const std::string& target, bool replace) : replace_(replace) {
  fs::path t = fs::absolute(fs::path(target)).lexically_normal();
  if (!t.has_filename()) t = t.parent_path();  // "out/" -> "out"
  target_ = t.string();
  std::error_code ec;
  if (fs::exists(t, ec)) {
    if (!fs::is_directory(t, ec)) {
      throw Error(target_ + ": exists and is not a directory (choose another --out)");
    }
    if (!is_empty_directory(t) && !replace_) {
      throw Error(target_ +
                  ": output directory exists and is not empty; choose another --out or pass "
                  "--force to replace its content");
    }
  }
  fs::create_directories(t.parent_path(), ec);
  if (ec) throw Error(t.parent_path().string() + ": cannot create directory: " + ec.message());
  remove_leftovers(t);
  staging_ = make_sibling(t, "partial");
  // mkdtemp makes the directory private (0700); results are ordinary files (0755 dirs).
  fs::permissions(staging_,
                  fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                      fs::perms::others_read | fs::perms::others_exec,
                  ec);
}

StagedDirectory::~StagedDirectory() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);  // best effort: a destructor must not throw
}

std::string StagedDirectory::map(const std::string& user_path) const {
  const fs::path p = fs::absolute(fs::path(user_path)).lexically_normal();
  const fs::path rel = p.lexically_relative(target_);
  if (rel.empty() || *rel.begin() == "..") return user_path;
  return (fs::path(staging_) / rel).string();
}

void StagedDirectory::commit() {
  const fs::path target(target_);
  std::error_code ec;
  if (fs::exists(target, ec) && !is_empty_directory(target)) {
    if (!replace_) throw Error(target_ + ": appeared during the run and is not empty");
    // Move the old content aside first, so that the target is never half old, half new.
    const std::string old = make_sibling(target, "old");
    fs::remove(old, ec);
    fs::rename(target, old, ec);
    if (ec) throw Error(target_ + ": cannot move the old output aside: " + ec.message());
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
}

}  // namespace rheo::output
