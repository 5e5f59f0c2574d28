// An output directory that appears only when everything in it was written: results go
// into a hidden temporary directory next to the target (same file system, so the final
// rename is atomic) and are moved into place by commit(). A run that fails, throws or is
// interrupted leaves nothing behind that could be mistaken for a result.
#pragma once

#include <string>
#include <vector>

namespace rheo::output {

class StagedDirectory {
 public:
  // Refuses (rheo::Error) when `target` exists and is not an empty directory, unless
  // `replace` is set; then the old content is replaced at commit(), not before. Creates
  // missing parent directories. `inputs` are the files and directories the command reads:
  // replacing a target that holds one of them (or the working directory) is refused here,
  // before any work, since the replacement would delete it. The staging is removed if the
  // command is interrupted (output/interrupt_cleanup.hpp).
  StagedDirectory(const std::string& target, bool replace,
                  const std::vector<std::string>& inputs = {});
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

  // Where to write a file the user named that goes with the results (a waveform): inside
  // the target as map(); outside it the file and the `companions` written beside it (a
  // save file) follow the same rule as the directory: refused now when one exists (unless
  // `replace`) or is an input, written to a hidden staging directory next to the file, and
  // moved into place by commit(). Returns the path to write.
  std::string stage_file(const std::string& user_path,
                         const std::vector<std::string>& companions = {});

  // Moves the staged results to the target (replacing an old target when allowed).
  void commit();

 private:
  struct StagedFile {
    std::string staging_dir;          // hidden directory next to the file
    std::vector<std::string> finals;  // absolute final paths (the file, its companions)
  };
  std::string target_;
  std::string staging_;
  bool replace_;
  std::vector<std::string> inputs_;
  std::vector<StagedFile> files_;
  bool committed_ = false;
};

}  // namespace rheo::output
