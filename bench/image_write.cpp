// image_write.cpp — clhair_bench_image_write: what writing a frame costs (bench/README.md,
// "Image writing").
//
//   clhair_bench_image_write FRAME.exr [--runs N] [--out DIR]
//
// Reads a rendered frame (render one with `clhair render SCENE --width 1920 --height 1080 -o
// frame.exr`), then, each N times (default 7) after one untimed warm-up, reports the median:
// - the linear -> 8-bit sRGB conversion of the frame, by the formula (one powf per value,
//   what writeImage did before) and by the threshold table (srgb_encode.h);
// - writeImage to PNG at every zlib level 0..9, and to OpenEXR with each compression: wall
//   time of the whole checked write (encode in memory, write, fsync, rename, fsync folder)
//   and file size.
// DIR (default: /dev/shm when it exists, else /tmp) holds the files; on a tmpfs the flushes
// cost nothing and the times are the encoders'. Prints a Markdown table.
//
//   clhair_bench_image_write --peak WIDTHxHEIGHT EXT [--out DIR]
//
// The memory of one write: a synthetic frame of that size (a gradient with fine stripes,
// every page touched) written once to DIR/peak.EXT; prints the process's peak resident size
// before and after the write, against the float image's own bytes (run it once per format:
// the peak is the process's whole life).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "clhair/error.h"
#include "clhair/image.h"
#include "io/srgb_encode.h"

namespace {

using namespace clhair;
using Clock = std::chrono::steady_clock;

template <typename F>
double medianMs(int runs, F f) {
  f();  // warm-up (first-use tables, page faults)
  std::vector<double> ms;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

// Peak resident size of this process so far, bytes.
double peakBytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0;  // Linux: KiB
}

int peakMode(int argc, char** argv) {
  int w = 0, h = 0;
  if (argc < 4 || std::sscanf(argv[2], "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0) {
    std::fprintf(stderr, "usage: clhair_bench_image_write --peak WIDTHxHEIGHT EXT [--out DIR]\n");
    return 2;
  }
  std::string out = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  if (argc >= 6 && std::string(argv[4]) == "--out") out = argv[5];
  const std::string path = out + "/clhair-peak." + argv[3];
  try {
    Image img;
    img.width = w;
    img.height = h;
    img.rgba.resize(std::size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        float* p = &img.rgba[(std::size_t(y) * w + x) * 4];
        const float stripe = 0.5f + 0.5f * std::sin(0.7f * x + 0.05f * y);
        p[0] = 0.6f * stripe * y / h;
        p[1] = 0.4f * stripe;
        p[2] = 0.2f * x / w;
        p[3] = stripe > 0.2f ? 1.0f : 0.5f;
      }
    const double image = static_cast<double>(img.rgba.size() * sizeof(float));
    const double before = peakBytes();
    const auto t0 = Clock::now();
    writeImage(img, path);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const double after = peakBytes();
    std::printf(
        "| %dx%d %s | float image %.0f MB | peak before %.0f MB | peak after %.0f MB | write "
        "adds %.0f MB (%.3fx the image; %.2f MB per megapixel) | peak %.3fx the image | %.0f ms "
        "| %ju bytes |\n",
        w, h, argv[3], image / 1e6, before / 1e6, after / 1e6, (after - before) / 1e6,
        (after - before) / image, (after - before) / 1e6 / (double(w) * h / 1e6), after / image, ms,
        std::filesystem::file_size(path));
    std::filesystem::remove(path);
  } catch (const Error& e) {
    std::fprintf(stderr, "clhair_bench_image_write: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "--peak") return peakMode(argc, argv);
  if (argc < 2) {
    std::fprintf(stderr, "usage: clhair_bench_image_write FRAME.exr [--runs N] [--out DIR]\n");
    return 2;
  }
  int runs = 7;
  std::string out = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--runs") runs = std::max(1, std::atoi(argv[i + 1]));
    if (a == "--out") out = argv[i + 1];
  }
  try {
    const Image frame = readImage(argv[1]);
    const std::size_t pixels = static_cast<std::size_t>(frame.width) * frame.height;
    out += "/clhair-bench-image-write";
    std::filesystem::create_directories(out);
    std::printf("frame %s: %dx%d, %d runs, files in %s\n\n", argv[1], frame.width, frame.height,
                runs, out.c_str());

    std::vector<std::uint8_t> bytes(pixels * 4);
    const double formula = medianMs(runs, [&] {
      for (std::size_t p = 0; p < pixels; ++p) {
        for (int c = 0; c < 3; ++c) bytes[p * 4 + c] = srgbByteFormula(frame.rgba[p * 4 + c]);
        bytes[p * 4 + 3] = alphaByte(frame.rgba[p * 4 + 3]);
      }
    });
    const std::vector<std::uint8_t> byFormula = bytes;
    const double table =
        medianMs(runs, [&] { encodeSrgb8(frame.rgba.data(), pixels, 4, bytes.data()); });
    std::printf("| sRGB conversion | median ms |\n|---|---|\n");
    std::printf(
        "| formula (powf per value) | %.2f |\n| threshold table | %.2f (%.1fx faster, "
        "%s) |\n\n",
        formula, table, formula / table, bytes == byFormula ? "byte-identical" : "DIFFERENT BYTES");

    std::printf(
        "| PNG zlib level | median ms | size (bytes) | size vs level 6 |\n|---|---|---|---|\n");
    std::vector<std::pair<double, std::uintmax_t>> png(10);
    for (int level = 0; level <= 9; ++level) {
      ImageWriteOptions o;
      o.pngCompression = level;
      const std::string path = out + "/level" + std::to_string(level) + ".png";
      png[level].first = medianMs(runs, [&] { writeImage(frame, path, o); });
      png[level].second = std::filesystem::file_size(path);
    }
    for (int level = 0; level <= 9; ++level)
      std::printf("| %d%s | %.1f | %ju | %.3f |\n", level,
                  level == ImageWriteOptions{}.pngCompression ? " (default)"
                  : level == 6                                ? " (OpenImageIO's default)"
                                                              : "",
                  png[level].first, png[level].second,
                  static_cast<double>(png[level].second) / static_cast<double>(png[6].second));

    std::printf("\n| EXR compression | median ms | size (bytes) |\n|---|---|---|\n");
    for (const std::string c :
         {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"}) {
      ImageWriteOptions o;
      o.exrCompression = c;
      const std::string path = out + "/" + c + ".exr";
      const double ms = medianMs(runs, [&] { writeImage(frame, path, o); });
      std::printf("| %s%s | %.1f | %ju |\n", c.c_str(),
                  c == ImageWriteOptions{}.exrCompression ? " (default)" : "", ms,
                  std::filesystem::file_size(path));
    }
    std::filesystem::remove_all(out);
  } catch (const Error& e) {
    std::fprintf(stderr, "clhair_bench_image_write: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
