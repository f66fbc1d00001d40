// outputs.h — what every `clhair` command that writes checks about its files before any work:
// each output (the main one and every side output: reports, error maps, tables) has a folder
// that exists and can be written, names no folder, device or FIFO, ends in an extension its
// writer makes, and is none of the command's inputs nor another of its outputs — compared
// through links, "..", and hard links (the same device and inode). A refusal is one
// clhair::Error line naming the flag, the path and the file it collides with.
#pragma once

#include <string>
#include <vector>

namespace clhair::cli {

// A file a command reads or writes, with what the user calls it ("-o", "--report", "the
// strand file").
struct NamedFile {
  std::string role;
  std::string path;
};

// An output and the extensions its writer accepts (lower case, with the dot; empty: any).
struct OutputFile {
  std::string flag;
  std::string path;
  std::vector<std::string> extensions;
  std::string format;  // the writer's format, for the hint ("hair-mesh JSON")
};

// True when `a` and `b` name one file: the same path once links and ".." are resolved, or
// (both existing) the same device and inode.
bool sameFile(const std::string& a, const std::string& b);

// A command's inputs, each identified once by its device and inode (an input exists, so an
// output that does not yet exist is none of them): check() costs one stat per output, for
// the frames of a long range.
class InputFiles {
 public:
  explicit InputFiles(const std::vector<NamedFile>& inputs);
  // Refuses `out` (given as `flag`) when it is one of the inputs.
  void check(const std::string& flag, const std::string& out) const;

 private:
  struct Entry {
    NamedFile file;
    unsigned long long device, inode;
  };
  std::vector<Entry> entries_;
};

// InputFiles(inputs).check(flag, out).
void checkNotAnInput(const std::string& flag, const std::string& out,
                     const std::vector<NamedFile>& inputs);

// Every check above, for every output, in the order given; outputs empty in `path` (a side
// output not asked for) are skipped.
void checkOutputs(const std::vector<OutputFile>& outputs, const std::vector<NamedFile>& inputs);

}  // namespace clhair::cli
