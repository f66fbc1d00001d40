// probe_kernel.h — runs one of kernels/bsdf_probe.cl's probe kernels, whose arguments are
// (input floats, record count, output): `count` records in work-groups of 64, the output read
// back with `canaries` elements past its end that the kernel must leave as they were.
#pragma once

#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "cl/device_impl.h"
#include "test_util.h"

namespace clhair::test {

// The first count x perRecord outputs of `kernel` over `in`.
template <class Out>
std::vector<Out> runProbeKernel(const char* kernel, const std::vector<float>& in, cl_uint count,
                                std::size_t perRecord, const Out& canary,
                                std::size_t canaries = 2) {
  auto& d = *sharedDevice().impl();
  cl::Kernel k(d.program("bsdf_probe.cl"), kernel);
  cl::Buffer ib(d.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, in.size() * sizeof(float),
                const_cast<float*>(in.data()));
  std::vector<Out> out(static_cast<std::size_t>(count) * perRecord + canaries, canary);
  cl::Buffer ob(d.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, out.size() * sizeof(Out),
                out.data());
  k.setArg(0, ib);
  k.setArg(1, count);
  k.setArg(2, ob);
  const std::size_t wg = 64, global = (count + wg - 1) / wg * wg;
  d.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(wg));
  d.queue.enqueueReadBuffer(ob, CL_TRUE, 0, out.size() * sizeof(Out), out.data());
  for (std::size_t i = out.size() - canaries; i < out.size(); ++i)
    EXPECT_EQ(std::memcmp(&out[i], &canary, sizeof(Out)), 0) << kernel << ": canary " << i;
  out.resize(static_cast<std::size_t>(count) * perRecord);
  return out;
}

}  // namespace clhair::test
