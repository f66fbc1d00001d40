// test_faults.cpp — nothing lost, nothing hangs: every file clhair writes, under a full file
// system, a read-only folder, a failing flush and a kill between writing and renaming, and
// every file it reads, given as a FIFO or a device (issue 27's fault families).
//
// Writers run in child processes: each library writer through clhair_write_probe (PNG, EXR,
// JPEG, HDR, TIFF, AOV EXR, cyHair, USC, TressFX, baked visibility, hair mesh, cage animation,
// raw bytes) and the command's own paths (render to PNG, EXR and JPEG, --frames, --aov,
// bake-visibility, export-strands, compare --error-map). After a failure the rules are: exit
// code not 0, exactly one "clhair: error:" line naming the file and the cause, no output
// created, an existing output byte-identical, no temporary left. A run killed before its
// rename leaves the target as it was; the next write of the target, and --skip-existing,
// remove the temporary it left. Full file systems are real (a small tmpfs) when the tests
// run as root, else the preload shim fails the writes (fault_fs.h); the shim always provides
// the kill and the failing fsync.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fault_fs.h"
#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The writers of clhair_write_probe and the file name each writes.
const std::vector<std::pair<std::string, std::string>> kProbeWriters = {
    {"png", "out.png"},         {"exr", "out.exr"},
    {"jpg", "out.jpg"},         {"hdr", "out.hdr"},
    {"tif", "out.tif"},         {"aov", "layers.exr"},
    {"hair", "strands.hair"},   {"data", "strands.data"},
    {"tfx", "strands.tfx"},     {"visibility", "bake.clhvis"},
    {"hairmesh", "groom.json"}, {"cage", "anim.cage"},
    {"ply", "strands.ply"},     {"bytes", "raw.bin"}};

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

std::size_t lineCount(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n + (!text.empty() && text.back() != '\n');
}

// A failed write: non-zero exit, one error line (and nothing else) holding the file and the
// cause, no temporary left in `dir`.
void expectFailedWrite(const CommandResult& r, const std::string& path, const std::string& cause,
                       const std::string& dir) {
  SCOPED_TRACE("output was:\n" + r.output);
  EXPECT_NE(r.exitCode, 0);
  EXPECT_EQ(countOf(r.output, "clhair: error:"), 1u);
  EXPECT_EQ(lineCount(r.output), 1u) << "more than the error line";
  const std::string line = onlyErrorLine(r.output);
  EXPECT_NE(line.find(path), std::string::npos) << "the line does not name " << path;
  EXPECT_NE(line.find(cause), std::string::npos) << "the line does not say \"" << cause << "\"";
  EXPECT_TRUE(temporariesIn(dir).empty()) << "a temporary was left in " << dir;
}

CommandResult probe(const std::string& env, const std::string& kind, const std::string& path) {
  return runCommand(env + quote(writeProbePath()) + " " + kind + " " + quote(path));
}

std::string previous(const std::string& name) { return "the previous contents of " + name; }

std::string canonical(const std::string& dir) { return fs::canonical(dir).string(); }

// Every writer into a folder where writes fail, in one probe process: each write gives exactly
// one error line naming its file and the cause; new files are not created, existing ones stay
// as they were, and no temporary is left.
void everyWriterRefused(const std::string& dir, const std::string& env, const std::string& cause) {
  std::string args;
  std::vector<std::string> targets;
  for (const auto& [kind, name] : kProbeWriters)
    for (const std::string& target : {dir + "/new_" + name, dir + "/" + name}) {
      args += " " + kind + " " + quote(target);
      targets.push_back(target);
    }
  const CommandResult r = runCommand(env + quote(writeProbePath()) + args);
  SCOPED_TRACE("output was:\n" + r.output);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(lineCount(r.output), targets.size()) << "one line per failed write";
  EXPECT_EQ(countOf(r.output, "clhair: error:"), targets.size());
  for (const std::string& target : targets) {
    SCOPED_TRACE(target);
    std::size_t named = 0;
    for (std::size_t p = r.output.find(target + ":"); p != std::string::npos;
         p = r.output.find(target + ":", p + 1)) {
      ++named;
      const std::size_t end = r.output.find('\n', p);
      EXPECT_NE(r.output.substr(p, end - p).find(cause), std::string::npos)
          << "its line does not say \"" << cause << "\"";
    }
    EXPECT_EQ(named, 1u) << "lines naming it";
    const std::string name = fs::path(target).filename().string();
    if (name.rfind("new_", 0) == 0) {
      EXPECT_FALSE(fs::exists(target)) << "was created";
    } else {
      EXPECT_EQ(readBytes(target), previous(name)) << "changed";
    }
  }
  EXPECT_TRUE(temporariesIn(dir).empty()) << "a temporary was left in " << dir;
}

std::map<std::string, std::string> existingTargets() {
  std::map<std::string, std::string> files;
  for (const auto& [kind, name] : kProbeWriters) files[name] = previous(name);
  return files;
}

TEST(Faults, EveryWriterOnAFullFileSystem) {
  const std::string dir = scratchDir() + "/full";
  FullFolder full(dir, existingTargets());
  RecordProperty("full_file_system", full.tmpfs() ? "tmpfs" : "preload shim");
  everyWriterRefused(dir, full.env(), FullFolder::cause());
}

// The shim stands in for a full disk where no tmpfs can be mounted: it must do the same.
TEST(Faults, EveryWriterOnAFullFileSystemThroughTheShim) {
  const std::string dir = scratchDir() + "/full";
  FullFolder full(dir, existingTargets(), /*forceShim=*/true);
  everyWriterRefused(dir, full.env(), FullFolder::cause());
}

TEST(Faults, EveryWriterInAReadOnlyFolder) {
  const std::string dir = scratchDir() + "/ro";
  ReadOnlyFolder ro(dir, existingTargets());
  if (!ro.tmpfs() && ::geteuid() == 0)
    GTEST_SKIP() << "root without a tmpfs mount: mode 0555 does not stop root from writing";
  everyWriterRefused(dir, "", ro.cause());
}

// A write cut short part-way and a flush that fails are failures too, with the byte counts.
TEST(Faults, ShortWriteAndFailingFlush) {
  const std::string dir = scratchDir();
  const std::string target = dir + "/out.png";
  writeBytes(target, previous("out.png"));
  const std::string where = "CLHAIR_FAULT_FULL_DIR=" + quote(canonical(dir));
  CommandResult r = probe(shimEnv(where + " CLHAIR_FAULT_FULL_BYTES=100"), "png", target);
  expectFailedWrite(r, target, "no space left on device", dir);
  // the file is written as it is encoded, so the count is of the bytes on disk
  EXPECT_NE(r.output.find("after 100 bytes"), std::string::npos) << r.output;
  EXPECT_EQ(readBytes(target), previous("out.png"));
  r = probe(shimEnv(where + " CLHAIR_FAULT_FULL_BYTES=100000000 CLHAIR_FAULT_FSYNC_EIO=1"), "png",
            target);
  expectFailedWrite(r, target, "input/output error", dir);
  EXPECT_EQ(readBytes(target), previous("out.png"));
}

// Killed between writing and renaming: the target is as it was and one temporary is left;
// the next write of the same target removes it. (Every writer ends in the same
// writeFileAtomically; the kinds the command writes most are each killed once.)
TEST(Faults, WritersKilledBeforeTheirRename) {
  const std::string dir = scratchDir();
  const std::vector<std::pair<std::string, std::string>> kinds = {
      {"png", "out.png"},           {"exr", "out.exr"},       {"jpg", "out.jpg"},
      {"aov", "layers.exr"},        {"hair", "strands.hair"}, {"tfx", "strands.tfx"},
      {"visibility", "bake.clhvis"}};
  std::string again;
  for (const auto& [kind, name] : kinds) {
    SCOPED_TRACE(kind);
    const std::string target = dir + "/" + name;
    writeBytes(target, previous(name));
    const std::size_t before = temporariesIn(dir).size();
    const CommandResult killed =
        probe(shimEnv("CLHAIR_FAULT_KILL_AT_RENAME=" + quote(canonical(dir))), kind, target);
    EXPECT_NE(killed.exitCode, 0) << killed.output;
    EXPECT_EQ(readBytes(target), previous(name)) << "the target changed before the rename";
    EXPECT_EQ(temporariesIn(dir).size(), before + 1) << "the killed run's temporary";
    again += " " + kind + " " + quote(target);
  }
  const CommandResult r = runCommand(quote(writeProbePath()) + again);
  EXPECT_EQ(r.exitCode, 0) << r.output;
  for (const auto& [kind, name] : kinds)
    EXPECT_NE(readBytes(dir + "/" + name), previous(name)) << kind << ": not written again";
  EXPECT_TRUE(temporariesIn(dir).empty()) << "the next writes left the killed runs' temporaries";
}

// ---- the command's own write paths -----------------------------------------------------------

json tinyScene() {
  return json{
      {"resolution", {40, 30}},
      {"camera", {{"position", {0.0, 0.03, 0.2}}, {"target", {0.0, 0.025, 0.0}}, {"fov", 35}}},
      {"lights", {{{"type", "directional"}, {"direction", {0.3, 0.8, 0.5}}}}},
      {"grooms", {{{"file", assetPath("grooms/tiny.hairmesh.json")}}}}};
}

std::string writeScene(const std::string& dir) {
  const std::string path = dir + "/scene.json";
  writeBytes(path, tinyScene().dump());
  return path;
}

TEST(Faults, CommandWritesOnAFullFileSystem) {
  const std::string work = scratchDir(), dir = work + "/full";
  const std::string scene = writeScene(work);
  // two small images for compare
  ASSERT_EQ(probe("", "png", work + "/a.png").exitCode, 0);
  ASSERT_EQ(probe("", "png", work + "/b.png").exitCode, 0);
  FullFolder full(
      dir, {{"existing.png", previous("existing.png")}, {"f.0001.png", previous("f.0001.png")}});
  const std::string cli = full.env() + quote(cliPath()) + " ";
  const std::string groom = quote(assetPath("grooms/tiny.hairmesh.json"));
  const struct {
    std::string args, target;
  } cases[] = {
      {"render " + quote(scene) + " -q -o ", "out.png"},
      {"render " + quote(scene) + " -q -o ", "existing.png"},
      {"render " + quote(scene) + " -q -o ", "out.exr"},
      {"render " + quote(scene) + " -q -o ", "out.jpg"},
      {"render " + quote(scene) + " -q --aov all -o ", "layers.exr"},
      {"compare " + quote(work + "/a.png") + " " + quote(work + "/b.png") + " --error-map ",
       "map.png"},
      {"export-strands " + groom + " -o ", "x.hair"},
      {"export-strands " + groom + " -o ", "x.tfx"},
      {"bake-visibility " + quote(scene) + " --rays 1 --points-per-cell 1 --cell-stride 64 -o ",
       "bake.clhvis"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args + c.target);
    const std::string target = dir + "/" + c.target;
    const CommandResult r = runCommand(cli + c.args + quote(target));
    EXPECT_NE(r.exitCode, 0);
    EXPECT_EQ(countOf(r.output, "clhair: error:"), 1u) << r.output;
    const std::string line = onlyErrorLine(r.output);
    EXPECT_NE(line.find(target), std::string::npos) << line;
    EXPECT_NE(line.find(FullFolder::cause()), std::string::npos) << line;
    EXPECT_TRUE(temporariesIn(dir).empty());
    if (c.target == "existing.png") {
      EXPECT_EQ(readBytes(target), previous("existing.png"));
    } else {
      EXPECT_FALSE(fs::exists(target)) << target << " was created";
    }
  }
  // a frame range stops at its first failed frame: one line, frame 1 kept, 2 and 3 never made
  const CommandResult r = runCommand(cli + "render " + quote(scene) + " -q --frames 1-3 -o " +
                                     quote(dir + "/f.####.png"));
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_EQ(lineCount(r.output), 1u) << r.output;
  EXPECT_NE(onlyErrorLine(r.output).find(dir + "/f.0001.png"), std::string::npos) << r.output;
  EXPECT_EQ(readBytes(dir + "/f.0001.png"), previous("f.0001.png"));
  EXPECT_FALSE(fs::exists(dir + "/f.0002.png"));
  EXPECT_FALSE(fs::exists(dir + "/f.0003.png"));
  EXPECT_TRUE(temporariesIn(dir).empty());
}

// A frame range killed before a rename leaves its frame as it was and a temporary; a resumed
// range (--skip-existing) removes it, and the frames are those an uninterrupted run writes.
TEST(Faults, KilledFrameRangeResumesAndCleansUp) {
  const std::string dir = scratchDir();
  const std::string scene = writeScene(dir);
  const std::string range =
      "render " + quote(scene) + " -q --frames 1-2 -o " + quote(dir + "/f.####.png");
  ASSERT_EQ(runCli(range).exitCode, 0);
  const std::string frame1 = readBytes(dir + "/f.0001.png"),
                    frame2 = readBytes(dir + "/f.0002.png");
  fs::remove(dir + "/f.0002.png");
  writeBytes(dir + "/f.0001.png", previous("f.0001.png"));
  // killed while finishing frame 1 (which already existed)
  const CommandResult killed =
      runCommand(shimEnv("CLHAIR_FAULT_KILL_AT_RENAME=" + quote(canonical(dir))) +
                 quote(cliPath()) + " " + range);
  EXPECT_NE(killed.exitCode, 0) << killed.output;
  EXPECT_EQ(readBytes(dir + "/f.0001.png"), previous("f.0001.png"));
  EXPECT_FALSE(fs::exists(dir + "/f.0002.png"));
  ASSERT_EQ(temporariesIn(dir).size(), 1u);
  // resumed: frame 1 exists and is skipped, its leftover temporary removed; frame 2 rendered
  const CommandResult resumed = runCli(range + " --skip-existing");
  EXPECT_EQ(resumed.exitCode, 0) << resumed.output;
  EXPECT_TRUE(temporariesIn(dir).empty()) << "--skip-existing left the killed run's temporary";
  EXPECT_EQ(readBytes(dir + "/f.0001.png"), previous("f.0001.png")) << "a skipped frame changed";
  EXPECT_EQ(readBytes(dir + "/f.0002.png"), frame2);
  EXPECT_FALSE(frame1.empty());
}

// ---- special files as inputs -------------------------------------------------------------

// Every input path given a FIFO and a link to /dev/zero: each command ends within 10 s with
// one error line naming the file, and writes nothing.
TEST(Faults, FifosAndDevicesRefusedForEveryInput) {
  const std::string dir = scratchDir();
  ASSERT_EQ(probe("", "png", dir + "/good.png").exitCode, 0);
  std::string script;
  std::vector<std::pair<std::string, std::string>> cases;  // (case name, special file name)
  const json base = tinyScene();
  // each input kind: the special file's name and how a scene (or the command line) uses it
  const struct {
    std::string kind, ext;
  } inputs[] = {{"scene", ".json"},        {"hair-mesh", ".json"}, {"cyhair", ".hair"},
                {"usc", ".data"},          {"tressfx", ".tfx"},    {"cage", ".cage"},
                {"visibility", ".clhvis"}, {"obj", ".obj"},        {"background", ".png"},
                {"environment", ".exr"},   {"compare", ".png"},    {"ply", ".ply"},
                {"ct2hair", ".bin"}};
  for (const std::string special : {"fifo", "device"}) {
    for (const auto& in : inputs) {
      const std::string name = special + "_" + in.kind;
      const std::string file = dir + "/" + name + in.ext;
      if (special == "fifo")
        ASSERT_EQ(::mkfifo(file.c_str(), 0644), 0) << file;
      else
        fs::create_symlink("/dev/zero", file);
      json s = base;
      std::string args;
      if (in.kind == "scene") {
        args = "render " + quote(file);
      } else if (in.kind == "compare") {
        args = "compare " + quote(file) + " " + quote(dir + "/good.png");
      } else {
        if (in.kind == "hair-mesh") s["grooms"][0]["file"] = file;
        if (in.kind == "cyhair" || in.kind == "usc" || in.kind == "tressfx" || in.kind == "ply" ||
            in.kind == "ct2hair")
          s["grooms"][0] = {{"strands_file", file}};
        if (in.kind == "cage") s["grooms"][0]["cage_animation"] = {{"file", file}};
        if (in.kind == "visibility") s["grooms"][0]["visibility"] = {{"file", file}};
        if (in.kind == "obj") s["meshes"] = {{{"file", file}}};
        if (in.kind == "background") s["background_image"] = file;
        if (in.kind == "environment") s["environment"] = {{"file", file}};
        writeBytes(dir + "/" + name + "_scene.json", s.dump());
        args = "render " + quote(dir + "/" + name + "_scene.json");
      }
      if (args.rfind("render", 0) == 0) args += " -q -o " + quote(dir + "/" + name + "_out.png");
      // four at a time: each command opens the OpenCL device
      script += "(timeout -s KILL 10 " + quote(cliPath()) + " " + args + " > " +
                quote(dir + "/" + name + ".log") + " 2>&1; echo $? > " +
                quote(dir + "/" + name + ".rc") + ") &\n";
      cases.push_back({name, file});
      if (cases.size() % 4 == 0) script += "wait\n";
    }
  }
  writeBytes(dir + "/all.sh", script + "wait\n");
  runCommand("sh " + quote(dir + "/all.sh"));
  for (const auto& [name, file] : cases) {
    SCOPED_TRACE(name);
    const std::string log = readBytes(dir + "/" + name + ".log");
    const std::string rc = readBytes(dir + "/" + name + ".rc");
    EXPECT_EQ(rc, "1\n") << "exit code (137: killed after 10 s, a hang):\n" << log;
    EXPECT_EQ(countOf(log, "clhair: error:"), 1u) << log;
    EXPECT_EQ(lineCount(log), 1u) << log;
    EXPECT_NE(log.find(fs::path(file).filename().string()), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(dir + "/" + name + "_out.png"));
  }
}

}  // namespace
}  // namespace clhair::test
