// cache_proof.h — a cached program binary proven in a child process before it is trusted.
//
// A cache entry's checksums prove that its bytes are the ones stored, not that the driver
// wrote a working binary in the first place (or that the disk stored what it was given): such
// a binary can crash the driver (SIGSEGV, SIGABRT) in every later run. So an entry is first
// built in a child process: proveCachedProgram starts this same executable (/proc/self/exe)
// with CLHAIR_CACHE_PROOF_* variables naming the device, the entry, its key and the build
// options; a static initializer in cache_proof.cpp sees them before main, builds the program
// from the entry, creates every kernel and asks each for its work-group size (drivers that
// generate code lazily do it there), and exits 0. A crash, a refusal, or no answer in 60 s
// fails the proof; the caller then removes the entry and builds from source. A proven entry
// is stamped (BinaryCache::markProven) so it is proven once, not on every start. Linked into
// a shared object (a Python module), where /proc/self/exe is another program, there is no
// child to start: the entry is trusted as its checksums leave it.
#pragma once

#include <string>

namespace clhair {

// True when the program stored in `entryPath` under `key` builds with `options` on device
// `deviceIndex` of platform `platformIndex` in a child process; else false with `why`.
bool proveCachedProgram(int platformIndex, int deviceIndex, const std::string& entryPath,
                        const std::string& key, const std::string& options, std::string& why);

}  // namespace clhair
