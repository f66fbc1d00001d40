// throughput.cpp — see throughput.h.
#include "throughput.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <deque>
#include <filesystem>
#include <memory>

#include "clhair/error.h"
#include "clhair/image.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "clhair/write_queue.h"

namespace clhair::bench {

namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// CPU time of the calling thread, ms (the host's own work, not the device's threads).
double threadCpuMs() {
  timespec t{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

std::string fmt(double v, int digits) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.*f", digits, v);
  return b;
}

// Frames per second with three significant digits (0.0412, 41.2, 412).
std::string fps(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.3g", v);
  return b;
}

std::string framePathOf(const std::string& dir, const std::string& ext, int n) {
  char b[32];
  std::snprintf(b, sizeof(b), "%04d", n);
  return dir + "/tp." + b + "." + ext;
}

struct Run {
  std::string mode, format;
  int frames = 0;
  double seconds = 0.0;      // the whole shot: first submit to last file written
  double wallMs = 0.0;       // median per frame (steady state)
  double deviceMs = 0.0;     // median device-time sum per frame
  double hostCpuMs = 0.0;    // render thread's CPU per frame
  double encodeCpuMs = 0.0;  // the writers' CPU per frame
  double waits = 0.0;        // host waits per frame (median)
  double fps() const { return seconds > 0.0 ? frames / seconds : 0.0; }
};

// The shot frame after frame. inFlight: Renderer::submit with 2 frames in flight and a
// WriteQueue; else render() and the write on the render thread, one frame at a time.
Run shot(const Device& dev, const Scene& scene, const ThroughputOptions& o, const std::string& ext,
         bool inFlight) {
  Renderer r(dev);
  r.setFramesInFlight(inFlight ? 2 : 1);
  RenderOptions ro;
  ro.timings = true;  // device times per frame (what the ratios are taken against)
  // warm-up: kernels built, maps allocated
  for (int f = 1; f <= 2; ++f) r.render(sceneAtFrame(scene, f), ro);
  Run run;
  run.mode = inFlight ? "in flight (2), writers" : "one at a time, write on the render thread";
  run.format = ext;
  run.frames = o.frames;
  std::vector<double> done, device, waits;
  std::atomic<long long> encodeUs{0};
  double hostCpu = 0.0;
  const auto t0 = Clock::now();
  {
    WriteQueue writers(inFlight ? 0u : 1u);
    auto write = [&](Frame f, int n) {
      auto image = std::make_shared<Image>(std::move(f.color));
      const std::string path = framePathOf(o.outDir, ext, n);
      auto job = [image, path, &encodeUs] {
        const double c0 = threadCpuMs();
        writeImage(*image, path);
        encodeUs += static_cast<long long>((threadCpuMs() - c0) * 1e3);
      };
      if (inFlight) {
        writers.submit(job);
      } else {
        job();
      }
    };
    auto took = [&](const Frame& f) {
      done.push_back(msSince(t0));
      device.push_back(f.totalMs());
      waits.push_back(static_cast<double>(f.stats.hostWaits));
    };
    std::deque<std::pair<FrameTicket, int>> pending;
    for (int n = 1; n <= o.frames; ++n) {
      const double c0 = threadCpuMs();
      const Scene s = sceneAtFrame(scene, n);
      if (inFlight) {
        pending.emplace_back(r.submit(s, ro), n);
        while (pending.size() > 2) {
          Frame f = r.wait(pending.front().first);
          took(f);
          write(std::move(f), pending.front().second);
          pending.pop_front();
        }
      } else {
        Frame f = r.render(s, ro);
        took(f);
        write(std::move(f), n);
      }
      hostCpu += threadCpuMs() - c0;
    }
    while (!pending.empty()) {
      const double c0 = threadCpuMs();
      Frame f = r.wait(pending.front().first);
      took(f);
      write(std::move(f), pending.front().second);
      pending.pop_front();
      hostCpu += threadCpuMs() - c0;
    }
    writers.finish();
  }
  run.seconds = msSince(t0) * 1e-3;
  std::vector<double> intervals;
  for (std::size_t i = 1; i < done.size(); ++i) intervals.push_back(done[i] - done[i - 1]);
  run.wallMs = median(intervals);
  run.deviceMs = median(device);
  run.hostCpuMs = hostCpu / o.frames;
  run.encodeCpuMs = static_cast<double>(encodeUs.load()) * 1e-3 / o.frames;
  run.waits = median(waits);
  return run;
}

}  // namespace

void throughputSection(const Device& dev, const ThroughputOptions& o, std::ostringstream& md,
                       nlohmann::json& report) {
  Scene scene = loadScene(o.scene);
  scene.width = o.width;
  scene.height = o.height;
  std::filesystem::create_directories(o.outDir);
  std::vector<Run> runs;
  std::vector<std::string> formats;
  for (std::size_t a = 0, b; a < o.formats.size(); a = b + 1) {
    b = o.formats.find(',', a);
    if (b == std::string::npos) b = o.formats.size();
    formats.push_back(o.formats.substr(a, b - a));
  }
  for (const std::string& ext : formats)
    for (bool inFlight : {true, false}) {
      runs.push_back(shot(dev, scene, o, ext, inFlight));
      const Run& r = runs.back();
      std::fprintf(stderr,
                   "throughput %s %s: %.3g frames/s, wall %.1f ms, device %.1f ms, host CPU %.1f "
                   "ms, encode CPU %.1f ms, waits %.0f per frame\n",
                   ext.c_str(), r.mode.c_str(), r.fps(), r.wallMs, r.deviceMs, r.hostCpuMs,
                   r.encodeCpuMs, r.waits);
    }
  // single still images: a process each (start-up, kernels from the cache, one frame, one
  // file), and in-process with a new Renderer each
  std::vector<double> process, inProcess;
  const std::string still = o.outDir + "/still.png";
  for (int i = 0; i < o.stills && !o.cli.empty(); ++i) {
    const std::string cmd = "'" + o.cli + "' render '" + o.scene + "' --width " +
                            std::to_string(o.width) + " --height " + std::to_string(o.height) +
                            " -q -o '" + still + "'";
    const auto t0 = Clock::now();
    if (std::system(cmd.c_str()) != 0) throw Error("throughput: `" + cmd + "` failed");
    process.push_back(msSince(t0));
  }
  std::vector<double> stillDevice;
  for (int i = 0; i < o.stills; ++i) {
    const auto t0 = Clock::now();
    Renderer r(dev);
    const Frame f = r.render(sceneAtFrame(scene, 1));
    writeImage(f.color, still);
    inProcess.push_back(msSince(t0));
    stillDevice.push_back(f.totalMs());
  }
  std::filesystem::remove_all(o.outDir);

  md << "\n## Throughput (" << o.scene.substr(o.scene.find_last_of('/') + 1) << ", " << o.width
     << "x" << o.height << ", " << o.frames << " frames per row)\n\n"
     << "Frames per second over the whole shot (first submit to last file written); per frame "
        "the median wall time between frames, the median device-time sum (profiling events), "
        "(wall - device) as a share of the wall time, the render thread's own CPU time, the "
        "writers' CPU time and the host's waits for the device.\n\n"
     << "| format | loop | frames/s | wall ms | device ms | wall - device | host CPU ms | "
        "encode CPU ms | host waits |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const Run& r : runs) {
    md << "| " << r.format << " | " << r.mode << " | " << fps(r.fps()) << " | " << fmt(r.wallMs, 1)
       << " | " << fmt(r.deviceMs, 1) << " | "
       << fmt(100.0 * (r.wallMs - r.deviceMs) / std::max(r.wallMs, 1e-9), 1) << " % | "
       << fmt(r.hostCpuMs, 1) << " | " << fmt(r.encodeCpuMs, 1) << " | " << fmt(r.waits, 0)
       << " |\n";
    report["throughput"]["runs"].push_back({{"format", r.format},
                                            {"loop", r.mode},
                                            {"frames", r.frames},
                                            {"frames_per_second", r.fps()},
                                            {"wall_ms", r.wallMs},
                                            {"device_ms", r.deviceMs},
                                            {"host_cpu_ms", r.hostCpuMs},
                                            {"encode_cpu_ms", r.encodeCpuMs},
                                            {"host_waits", r.waits}});
  }
  for (std::size_t i = 0; i + 1 < runs.size(); i += 2)
    md << "\n"
       << runs[i].format << ": frames in flight " << fmt(runs[i].fps(), 2) << " frames/s against "
       << fmt(runs[i + 1].fps(), 2) << " one at a time ("
       << fmt(runs[i].fps() / std::max(runs[i + 1].fps(), 1e-9), 2)
       << "x); frame rate against 1 / device time: "
       << fmt(runs[i].fps() * runs[i].deviceMs * 1e-3, 3) << ".";
  md << "\n\nSingle still images (frame 1 of the shot, written as PNG), median of " << o.stills
     << ": a `clhair render` process each " << fmt(median(process), 0)
     << " ms; in-process with a new Renderer each " << fmt(median(inProcess), 0)
     << " ms, of which device time " << fmt(median(stillDevice), 0) << " ms.\n";
  report["throughput"]["still_process_ms"] = median(process);
  report["throughput"]["still_in_process_ms"] = median(inProcess);
  report["throughput"]["still_device_ms"] = median(stillDevice);
}

}  // namespace clhair::bench
