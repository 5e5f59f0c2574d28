#include "host/output/staged_directory.hpp"

#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "sim/error.hpp"

namespace rheo::output {

namespace fs = std::filesystem;

namespace {

bool is_empty_directory(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec) && fs::is_empty(p, ec);
}

// A unique sibling name from a mkdtemp(3) template (so two runs never share one).
std::string make_sibling(const fs::path& target, const std::string& tag) {
  // Built with append() rather than operator+ chains, which trip GCC 12's -Wrestrict.
  std::string name(".");
  name.append(target.filename().string()).append(".").append(tag).append("-XXXXXX");
  const std::string templ = (target.parent_path() / name).string();
  std::vector<char> buf(templ.begin(), templ.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) {
    throw Error(templ + ": cannot create a temporary directory next to the output: " +
                std::strerror(errno));
  }
  return std::string(buf.data());
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
