// test_readme.cpp — the README's examples and the docs' links, checked against the tree.
//
// Examples: every fenced ```sh block of README.md preceded by a comment line
//   <!-- readme-test NAME: FILE=WxH FILE=WxH[CHANNEL,CHANNEL] ... -->
// is run as a bash script (`set -e`) in a fresh folder of its own that holds only `assets`
// (a link to the source tree's) and `build/clhair` (a link to the built CLI), so the commands
// run exactly as printed, as from the repository root after `scripts/dev.sh demo`. The block
// must exit 0, and every FILE it names must then exist and be an image of W x H pixels whose
// colour is not one flat value (hair was drawn on the background), holding every CHANNEL
// listed in brackets. The README must mark the four examples the users' guide promises:
// render, sequence, aov and own-groom.
// Links: every relative link and image in README.md, docs/*.md and bench/*.md (inline
// `[text](target)`, reference definitions `[name]: target`, and HTML `src`/`href`), outside
// code, must name a file or folder that exists relative to the document, and a `#anchor` into
// a Markdown file must match one of its headings as GitHub turns headings into anchors.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace clhair::test {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) out.push_back(line);
  return out;
}

struct ExpectedImage {
  std::string file;
  int width = 0, height = 0;
  std::vector<std::string> channels;
};

struct Example {
  std::string name;
  std::string script;
  std::vector<ExpectedImage> outputs;
  std::string error;  // a malformed marker or block, reported by the test
};

// The marked ```sh blocks of README.md, in order.
std::vector<Example> readmeExamples() {
  static const std::regex marker(R"(^<!-- readme-test ([a-z0-9-]+):(.*)-->\s*$)");
  static const std::regex expect(R"(^([^=\s]+)=(\d+)x(\d+)(?:\[([^\]]*)\])?$)");
  const std::vector<std::string> text = lines(readText(fs::path(sourceDir()) / "README.md"));
  std::vector<Example> out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    std::smatch m;
    if (!std::regex_match(text[i], m, marker)) continue;
    Example ex;
    ex.name = m[1];
    std::stringstream outputs(m[2].str());
    for (std::string item; outputs >> item;) {
      std::smatch e;
      if (!std::regex_match(item, e, expect)) {
        ex.error = "output \"" + item + "\" is not FILE=WxH or FILE=WxH[CHANNELS]";
        continue;
      }
      ExpectedImage img{e[1], std::stoi(e[2]), std::stoi(e[3]), {}};
      std::stringstream ch(e[4].str());
      for (std::string c; std::getline(ch, c, ',');)
        if (!c.empty()) img.channels.push_back(c);
      ex.outputs.push_back(img);
    }
    if (ex.outputs.empty() && ex.error.empty()) ex.error = "the marker names no output file";
    if (i + 1 >= text.size() || text[i + 1] != "```sh") {
      ex.error = "the marker is not followed by a ```sh block";
    } else {
      std::size_t j = i + 2;
      for (; j < text.size() && text[j] != "```"; ++j) ex.script += text[j] + "\n";
      if (j == text.size()) ex.error = "the ```sh block is not closed";
      i = j;
    }
    out.push_back(ex);
  }
  return out;
}

std::vector<std::string> exampleNames() {
  std::vector<std::string> names;
  for (const Example& e : readmeExamples()) names.push_back(e.name);
  return names;
}

TEST(Readme, MarksTheRenderSequenceAovAndOwnGroomExamples) {
  const std::vector<std::string> names = exampleNames();
  for (const char* want : {"render", "sequence", "aov", "own-groom"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end())
        << "README.md has no block marked <!-- readme-test " << want << ": ... -->";
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size())
      << "two README examples share a name";
}

class ReadmeExample : public ::testing::TestWithParam<std::string> {};

TEST_P(ReadmeExample, RunsAndWritesItsImages) {
  Example ex;
  for (const Example& e : readmeExamples())
    if (e.name == GetParam()) ex = e;
  ASSERT_EQ(ex.name, GetParam()) << "the example is no longer in README.md";
  ASSERT_TRUE(ex.error.empty()) << "README example " << ex.name << ": " << ex.error;

  // A fresh folder that looks like the repository root after a build, and nothing more.
  const fs::path dir = scratchDir();
  fs::create_directories(dir / "build");
  fs::create_symlink(fs::absolute(cliPath()), dir / "build" / "clhair");
  fs::create_directory_symlink(fs::path(sourceDir()) / "assets", dir / "assets");
  {
    std::ofstream script(dir / "example.sh", std::ios::binary);
    script << "set -e\n" << ex.script;
  }
  const CommandResult r = runCommand("cd " + quote(dir.string()) + " && bash example.sh");
  ASSERT_EQ(r.exitCode, 0) << "README example " << ex.name << " failed:\n"
                           << ex.script << "---\n"
                           << r.output;

  for (const ExpectedImage& want : ex.outputs) {
    SCOPED_TRACE(ex.name + ": " + want.file);
    const fs::path path = dir / want.file;
    ASSERT_TRUE(fs::is_regular_file(path)) << path << " was not written";
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    const OIIO::ImageSpec spec = in->spec();
    EXPECT_EQ(spec.width, want.width);
    EXPECT_EQ(spec.height, want.height);
    for (const std::string& c : want.channels)
      EXPECT_GE(spec.channelindex(c), 0) << "no channel " << c;
    ASSERT_GE(spec.nchannels, 3);
    std::vector<float> rgb(static_cast<std::size_t>(spec.width) * spec.height * 3);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, rgb.data())) << in->geterror();
    const auto [lo, hi] = std::minmax_element(rgb.begin(), rgb.end());
    EXPECT_GT(*hi - *lo, 0.02f) << "the image is one flat colour: nothing was drawn";
  }
}

INSTANTIATE_TEST_SUITE_P(Readme, ReadmeExample, ::testing::ValuesIn(exampleNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

// ---- links -----------------------------------------------------------------------------

// The text with fenced code blocks and inline code spans blanked (links there are examples).
std::string withoutCode(const std::string& text) {
  std::string out;
  bool fenced = false;
  for (const std::string& line : lines(text)) {
    const std::size_t lead = line.find_first_not_of(' ');
    if (lead != std::string::npos && line.compare(lead, 3, "```") == 0) {
      fenced = !fenced;
      out += "\n";
      continue;
    }
    if (fenced) {
      out += "\n";
      continue;
    }
    std::string kept;
    bool code = false;
    for (char c : line) {
      if (c == '`') code = !code;
      kept += code || c == '`' ? ' ' : c;
    }
    out += kept + "\n";
  }
  return out;
}

// A heading's anchor as GitHub makes it: lower case, punctuation dropped, spaces as '-'.
std::string anchorOf(const std::string& heading) {
  std::string a;
  for (unsigned char c : heading) {
    if (std::isalnum(c))
      a += static_cast<char>(std::tolower(c));
    else if (c == ' ' || c == '-')
      a += '-';
    else if (c == '_')
      a += '_';
  }
  return a;
}

std::set<std::string> anchorsOf(const fs::path& markdown) {
  std::set<std::string> anchors;
  for (const std::string& line : lines(withoutCode(readText(markdown)))) {
    const std::size_t hashes = line.find_first_not_of('#');
    if (hashes == 0 || hashes == std::string::npos || hashes > 6 || line[hashes] != ' ') continue;
    const std::string anchor = anchorOf(line.substr(hashes + 1));
    // Repeated headings get -1, -2, ... after the first.
    std::string unique = anchor;
    for (int n = 1; anchors.count(unique); ++n) unique = anchor + "-" + std::to_string(n);
    anchors.insert(unique);
  }
  return anchors;
}

std::vector<std::string> linkTargets(const std::string& text) {
  static const std::regex inline_link(R"(\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\))");
  static const std::regex definition(R"((?:^|\n)\s{0,3}\[[^\]]+\]:\s*<?([^\s>]+))");
  static const std::regex html(R"re((?:src|href)\s*=\s*"([^"]+)")re");
  const std::string t = withoutCode(text);
  std::vector<std::string> out;
  for (const std::regex* re : {&inline_link, &definition, &html})
    for (auto it = std::sregex_iterator(t.begin(), t.end(), *re); it != std::sregex_iterator();
         ++it)
      out.push_back((*it)[1]);
  return out;
}

TEST(Readme, RelativeLinksInReadmeAndDocsPointToFilesThatExist) {
  const fs::path root = sourceDir();
  std::vector<fs::path> docs = {root / "README.md"};
  for (const char* folder : {"docs", "bench"})
    for (const auto& e : fs::directory_iterator(root / folder))
      if (e.path().extension() == ".md") docs.push_back(e.path());
  ASSERT_TRUE(fs::exists(root / "docs" / "README.md")) << "docs/README.md, the index, is missing";

  std::size_t checked = 0, readmeLinks = 0;
  for (const fs::path& doc : docs) {
    for (std::string target : linkTargets(readText(doc))) {
      if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) continue;
      std::string anchor;
      if (const std::size_t h = target.find('#'); h != std::string::npos) {
        anchor = target.substr(h + 1);
        target.erase(h);
      }
      const fs::path file = target.empty() ? doc : doc.parent_path() / target;
      const std::string where = fs::relative(doc, root).string() + ": link \"" + target +
                                (anchor.empty() ? "" : "#" + anchor) + "\"";
      ++checked;
      if (doc == root / "README.md") ++readmeLinks;
      if (!fs::exists(file)) {
        ADD_FAILURE() << where << " points to " << fs::relative(file.lexically_normal(), root)
                      << ", which does not exist";
        continue;
      }
      if (!anchor.empty() && file.extension() == ".md" && !anchorsOf(file).count(anchor))
        ADD_FAILURE() << where << ": " << fs::relative(file.lexically_normal(), root)
                      << " has no heading with the anchor #" << anchor;
    }
  }
  // The scan must have found the links it exists to check.
  EXPECT_GE(readmeLinks, 10u);
  EXPECT_GE(checked, 40u);
}

}  // namespace
}  // namespace clhair::test
