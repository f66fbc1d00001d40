// outputs.cpp — the checks of a command's outputs before any work (outputs.h).
#include "outputs.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>

#include "clhair/error.h"
#include "io/json_util.h"
#include "io/safe_write.h"

namespace clhair::cli {

namespace fs = std::filesystem;

bool sameFile(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  std::error_code ea, eb;
  const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
  if (!ea && !eb && ca == cb) return true;
  struct stat sa {
  }, sb{};
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
         sa.st_ino == sb.st_ino;
}

InputFiles::InputFiles(const std::vector<NamedFile>& inputs) {
  for (const NamedFile& in : inputs) {
    struct stat st {};
    if (in.path.empty() || ::stat(in.path.c_str(), &st) != 0) continue;
    entries_.push_back({in, static_cast<unsigned long long>(st.st_dev),
                        static_cast<unsigned long long>(st.st_ino)});
  }
}

void InputFiles::check(const std::string& flag, const std::string& out) const {
  struct stat st {};
  if (entries_.empty() || ::stat(out.c_str(), &st) != 0) return;
  for (const Entry& e : entries_)
    if (e.device == static_cast<unsigned long long>(st.st_dev) &&
        e.inode == static_cast<unsigned long long>(st.st_ino))
      throw Error(flag + " \"" + out + "\" is " + e.file.role + " (\"" + e.file.path +
                  "\"): writing it would replace an input of this command (nothing was "
                  "written; choose another output file)");
}

void checkNotAnInput(const std::string& flag, const std::string& out,
                     const std::vector<NamedFile>& inputs) {
  InputFiles(inputs).check(flag, out);
}

void checkOutputs(const std::vector<OutputFile>& outputs, const std::vector<NamedFile>& inputs) {
  const InputFiles in(inputs);
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const OutputFile& o = outputs[i];
    if (o.path.empty()) continue;
    // what would be lost first: an input, or another output of the same run
    in.check(o.flag, o.path);
    for (std::size_t k = 0; k < i; ++k)
      if (sameFile(o.path, outputs[k].path))
        throw Error(o.flag + " \"" + o.path + "\" is also " + outputs[k].flag +
                    ": give each output its own file");
    if (!o.extensions.empty()) {
      const std::string ext = lowerExtension(o.path);
      bool known = false;
      std::string list;
      for (const std::string& e : o.extensions) {
        known = known || e == ext;
        list += (list.empty() ? "" : ", ") + e;
      }
      if (!known)
        throw Error(o.flag + " \"" + o.path + "\": " +
                    (ext.empty() ? std::string("has no extension")
                                 : "the extension \"" + ext + "\" is not one") +
                    " the " + o.format + " writer makes (use " + list + ")");
    }
    try {
      checkOutputPath(o.path);
    } catch (const Error& e) {
      throw Error(o.flag + ": " + e.what());
    }
    const std::string folder = fs::path(o.path).parent_path().empty()
                                   ? std::string(".")
                                   : fs::path(o.path).parent_path().string();
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
      throw Error(o.flag + " \"" + o.path + "\": cannot write into " + folder + " (" +
                  errnoText(errno) + ")");
  }
}

}  // namespace clhair::cli
