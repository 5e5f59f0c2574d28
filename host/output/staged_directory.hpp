// An output directory that appears only when everything in it was written: results go
// into a hidden temporary directory next to the target (same file system, so the final
// rename is atomic) and are moved into place by commit(). A run that fails, throws or is
// interrupted leaves nothing behind that could be mistaken for a result.
#pragma once

#include <string>

namespace rheo::output {

class StagedDirectory {
 public:
  // Refuses (rheo::Error) when `target` exists and is not an empty directory, unless
  // `replace` is set; then the old content is replaced at commit(), not before. Creates
  // missing parent directories.
  StagedDirectory(const std::string& target, bool replace);
  ~StagedDirectory();  // removes the temporary directory unless committed
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  // Where to write now.
  const std::string& path() const { return staging_; }
  // Where the results will be after commit().
  const std::string& target() const { return target_; }

  // Where to write a file the user named: a path inside the target directory is written at
  // its place in the staging directory (so it appears with the rest at commit()); any
  // other path is returned unchanged.
  std::string map(const std::string& user_path) const;

  // Moves the staged results to the target (replacing an old target when allowed).
  void commit();

 private:
  std::string target_;
  std::string staging_;
  bool replace_;
  bool committed_ = false;
};

}  // namespace rheo::output
