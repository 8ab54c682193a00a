#pragma once
// Outputs that are never half-written or lost.
//
// A file is written to a temporary name in its own directory, flushed to the disk, and renamed
// over the target: a reader sees the old file or the new one, never a mix, and a failure or a
// kill leaves the old one intact. A set of files that belong together (a frame's raw buffers,
// an explanation's pictures) is a directory written the same way: built under a temporary name
// beside the target, then exchanged with it in one rename. Such a directory ends with a
// manifest.json naming its files; hsr replaces only a directory that is empty or holds such a
// manifest, never one holding files it did not write.
//
// Every failure throws hsr::Error with one line naming the file and the reason ("No space left
// on device"), after removing the temporaries. A process killed by SIGINT or SIGTERM leaves no
// temporaries when its handler calls removeTemporaryOutputs (the CLI installs one).

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace hsr {

// Writes the pieces, one after another, to `path` atomically (see above).
void writeFileAtomically(const std::filesystem::path& path,
                         std::initializer_list<std::string_view> pieces);

// A directory written as a whole. Names are plain file names (no separators).
class OutputDirectory {
 public:
  // Refuses (hsr::Error) when `dir` exists and is not a directory, or holds files that hsr
  // did not write: it has no manifest.json and some file is not among `own_names` (the names
  // an hsr from before manifests wrote there). Creates the temporary directory beside it.
  explicit OutputDirectory(std::filesystem::path dir, std::vector<std::string> own_names = {});
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;
  ~OutputDirectory();  // not committed: the temporary directory and its files are removed

  void write(std::string_view name, std::initializer_list<std::string_view> pieces);
  // Writes manifest.json (the files, their sizes, and `about`, a JSON object's members or
  // empty) and puts the directory in place of the old one, which is then removed.
  void commit(std::string_view about = {});

  const std::filesystem::path& path() const { return dir_; }

 private:
  std::filesystem::path dir_, temporary_;
  std::vector<std::pair<std::string, std::size_t>> files_;
  int slot_ = -1;
  bool committed_ = false;
};

// Throws hsr::Error when OutputDirectory(dir, own_names) would refuse `dir`: a check before
// any work is done.
void checkOutputDirectory(const std::filesystem::path& dir,
                          const std::vector<std::string>& own_names = {});

// Async-signal-safe: removes every temporary file and directory this process is writing.
void removeTemporaryOutputs() noexcept;

// Async-signal-safe: writes to `fd` one line naming the outputs (files and directories) this
// process has replaced so far, in the order it replaced them (the first 16, then "..."), or
// that it has replaced none: what a reader finds after a run stopped by a signal. One run's
// outputs are replaced one after another, each whole (docs/reliability.md).
void reportReplacedOutputs(int fd) noexcept;

}  // namespace hsr
