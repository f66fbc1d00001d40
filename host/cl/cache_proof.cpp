// cache_proof.cpp — the child-process proof of a cached program binary (cache_proof.h): the
// parent's spawn and wait, and the child's side, run from a static initializer before main
// in whichever executable links the library (clhair, the tests, the bench).
#include "cl/cache_proof.h"

#include <dlfcn.h>
#include <fcntl.h>
#include <link.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include "cl/binary_cache.h"
#include "cl/opencl.h"
#include "io/regular_file.h"

extern char** environ;

namespace clhair {

namespace {

constexpr const char* kDevice = "CLHAIR_CACHE_PROOF_DEVICE";
constexpr const char* kEntry = "CLHAIR_CACHE_PROOF_ENTRY";
constexpr const char* kKey = "CLHAIR_CACHE_PROOF_KEY";
constexpr const char* kOptions = "CLHAIR_CACHE_PROOF_OPTIONS";
constexpr int kTimeoutSeconds = 60;

// Exit codes of the child (anything else, or a signal, is a crash).
enum ProofExit { kProven = 0, kRefused = 3, kUnreadable = 4, kNoKernels = 5 };

// The child: build the entry's program and create its kernels; never returns.
[[noreturn]] void proveHere(const char* device, const char* entry, const char* key,
                            const char* options) {
  int code = kRefused;
  try {
    int p = 0, d = 0;
    if (std::sscanf(device, "%d:%d", &p, &d) != 2) std::_Exit(kRefused);
    std::vector<cl::Platform> platforms;
    cl::Platform::get(&platforms);
    std::vector<cl::Device> devices;
    platforms.at(static_cast<std::size_t>(p)).getDevices(CL_DEVICE_TYPE_ALL, &devices);
    const cl::Device dev = devices.at(static_cast<std::size_t>(d));
    std::string bytes;
    try {
      RegularFile f(entry, "cache entry");
      bytes = f.readAll(std::uint64_t(1) << 30);
    } catch (const std::exception&) {
      std::_Exit(kUnreadable);
    }
    const auto payload = decodeCacheEntry(bytes, key);
    if (!payload) std::_Exit(kUnreadable);
    cl::Context context(dev);
    cl::Program program(context, {dev}, cl::Program::Binaries{*payload});
    program.build({dev}, options);
    std::vector<cl::Kernel> kernels;
    program.createKernels(&kernels);
    for (const cl::Kernel& k : kernels) k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(dev);
    code = kernels.empty() ? kNoKernels : kProven;
  } catch (...) {
    code = kRefused;
  }
  std::_Exit(code);
}

int proofIfAsked() {
  const char* entry = std::getenv(kEntry);
  if (!entry) return 0;
  const char* device = std::getenv(kDevice);
  const char* key = std::getenv(kKey);
  const char* options = std::getenv(kOptions);
  if (!device || !key || !options) std::_Exit(kRefused);
  proveHere(device, entry, key, options);
}

// Runs before main in the child; 0 and nothing else in every other process.
const int kProofRun = proofIfAsked();

// True when this code is part of the executable itself (its link map has no name), not of a
// shared object loaded into another program (a Python interpreter): only then does
// /proc/self/exe run the static initializer above.
bool inTheExecutable() {
  Dl_info info{};
  link_map* map = nullptr;
  return ::dladdr1(reinterpret_cast<void*>(&proofIfAsked), &info, reinterpret_cast<void**>(&map),
                   RTLD_DL_LINKMAP) != 0 &&
         map && map->l_name && map->l_name[0] == '\0';
}

}  // namespace

bool proveCachedProgram(int platformIndex, int deviceIndex, const std::string& entryPath,
                        const std::string& key, const std::string& options, std::string& why) {
  (void)kProofRun;
  // inside a shared object the executable is someone else's: the entry is trusted as the
  // checksums leave it (cache_proof.h)
  if (!inTheExecutable()) return true;
  std::vector<std::string> env;
  for (char** e = environ; e && *e; ++e)
    if (std::strncmp(*e, "CLHAIR_CACHE_PROOF_", 19) != 0) env.emplace_back(*e);
  env.push_back(std::string(kDevice) + "=" + std::to_string(platformIndex) + ":" +
                std::to_string(deviceIndex));
  env.push_back(std::string(kEntry) + "=" + entryPath);
  env.push_back(std::string(kKey) + "=" + key);
  env.push_back(std::string(kOptions) + "=" + options);
  std::vector<char*> envp;
  for (std::string& s : env) envp.push_back(s.data());
  envp.push_back(nullptr);
  char name[] = "clhair-cache-proof";
  char* argv[] = {name, nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  // the driver's own complaints stay out of the user's terminal
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv, envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    why = std::string("the check could not start (") + std::strerror(spawned) + ")";
    return false;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kTimeoutSeconds);
  int status = 0;
  for (auto wait = std::chrono::microseconds(500);;) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) {
      why = "the check's process was lost";
      return false;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      why = "the check gave no answer in " + std::to_string(kTimeoutSeconds) + " s";
      return false;
    }
    std::this_thread::sleep_for(wait);
    wait = std::min(wait * 2, std::chrono::microseconds(20000));
  }
  if (WIFSIGNALED(status)) {
    why = std::string("the driver crashed building it (") + strsignal(WTERMSIG(status)) + ")";
    return false;
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == kProven) return true;
  why = code == kUnreadable  ? "the entry could not be read back"
        : code == kNoKernels ? "the program holds no kernels"
                             : "the driver refused it";
  return false;
}

}  // namespace clhair
