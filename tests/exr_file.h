// exr_file.h — an EXR read back with OpenImageIO for the tests: every channel as a float
// plane by name, its stored type, and the header's string attributes.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

namespace clhair::test {

struct ExrFile {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> channels;
  std::map<std::string, OIIO::TypeDesc> types;
  std::map<std::string, std::string> header;
};

inline ExrFile readExr(const std::string& path) {
  ExrFile f;
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    ADD_FAILURE() << "cannot open " << path << ": " << OIIO::geterror();
    return f;
  }
  const OIIO::ImageSpec& spec = in->spec();
  f.width = spec.width;
  f.height = spec.height;
  const int n = spec.nchannels;
  std::vector<float> data(static_cast<std::size_t>(f.width) * f.height * n);
  EXPECT_TRUE(in->read_image(0, 0, 0, n, OIIO::TypeDesc::FLOAT, data.data())) << in->geterror();
  for (int c = 0; c < n; ++c) {
    std::vector<float>& plane = f.channels[spec.channelnames[c]];
    plane.resize(static_cast<std::size_t>(f.width) * f.height);
    for (std::size_t p = 0; p < plane.size(); ++p) plane[p] = data[p * n + c];
    f.types[spec.channelnames[c]] = spec.channelformat(c);
  }
  for (const OIIO::ParamValue& a : spec.extra_attribs)
    if (a.type() == OIIO::TypeDesc::STRING) f.header[a.name().string()] = a.get_string();
  return f;
}

}  // namespace clhair::test
