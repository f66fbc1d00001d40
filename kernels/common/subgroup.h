/* subgroup.h — the sub-group layer: neighbour exchange between the lanes of one strand.
 *
 * A logical sub-group is SG_SIZE lanes that assemble and draw one strand together; a
 * work-group holds SG_STRANDS of them (strand slot sg_slot(), lane sg_lane()). SG_SIZE and
 * SG_STRANDS come from the host's per-device tuning table (host/cl/tuning.cpp): 32 lanes
 * and one strand per group on GPUs; on CPUs the `single` backend, one lane per strand and
 * many strands per group, so a strand is plain sequential code with private scratch and
 * no barriers. Kernels name the strand of a work-item with sg_strand_index() and share
 * per-strand scratch through SG_SHARED arrays indexed by sg_slot(), synchronised with
 * sg_barrier(); none of them assumes a lane count. The layer offers shuffles of 32-bit
 * words and of uint4/float4 (component-wise), with the edge lane's result given by `fill`:
 *   sg_shuffle_up1(c, x, fill)   lane i receives x of lane i-1; lane 0 receives fill
 *   sg_shuffle_down1(c, x, fill) lane i receives x of lane i+1; the last lane gets fill
 *   sg_broadcast0(c, x)          every lane receives x of lane 0
 * Every lane must reach every call (predicate idle lanes, never return early before one).
 *
 * Backends (SG_BACKEND, chosen by the host and checked by a start-up self-test):
 *   SG_BACKEND_LOCAL  __local ping-pong buffer, one barrier per exchange (any device)
 *   SG_BACKEND_KHR    cl_khr_subgroup_shuffle_relative (OpenCL C 2.0+)
 *   SG_BACKEND_INTEL  cl_intel_subgroups
 *   SG_BACKEND_NVPTX  inline PTX shfl.sync (SG_PTX_LEGACY_SHFL=1: plain shfl before sm_70)
 *   SG_BACKEND_AMD    __builtin_amdgcn_ds_bpermute
 *   SG_BACKEND_SINGLE one lane (SG_SIZE 1): every shuffle returns its fill (CPUs)
 * Only the single backend may put several strands in a work-group (SG_STRANDS > 1): the
 * other backends synchronise through work-group barriers, which every strand of the group
 * would have to reach the same number of times.
 * The ping-pong buffer alternates halves, so exchange k+2 may overwrite the half that
 * exchange k read: the barrier of exchange k+1 separates them.
 */
#ifndef CLHAIR_SUBGROUP_H
#define CLHAIR_SUBGROUP_H

#define SG_BACKEND_LOCAL 0
#define SG_BACKEND_KHR 1
#define SG_BACKEND_INTEL 2
#define SG_BACKEND_NVPTX 3
#define SG_BACKEND_AMD 4
#define SG_BACKEND_SINGLE 5

#ifndef SG_BACKEND
#define SG_BACKEND SG_BACKEND_LOCAL
#endif
#ifndef SG_SIZE
#if SG_BACKEND == SG_BACKEND_SINGLE
#define SG_SIZE 1
#else
#define SG_SIZE 32
#endif
#endif
#ifndef SG_STRANDS
#define SG_STRANDS 1
#endif
#if SG_STRANDS > 1 && SG_BACKEND != SG_BACKEND_SINGLE
#error "several strands per work-group need the single-lane backend (SG_BACKEND_SINGLE)"
#endif
#if SG_BACKEND == SG_BACKEND_SINGLE && SG_SIZE != 1
#error "the single-lane backend has SG_SIZE 1"
#endif
#define SG_GROUP_SIZE (SG_SIZE * SG_STRANDS)

#if SG_BACKEND == SG_BACKEND_KHR
/* OpenCL C 3.0 devices may offer only the __opencl_c_subgroups feature */
#if defined(cl_khr_subgroups)
#pragma OPENCL EXTENSION cl_khr_subgroups : enable
#endif
#elif SG_BACKEND == SG_BACKEND_INTEL
#pragma OPENCL EXTENSION cl_intel_subgroups : enable
#endif

/* Kernel attributes of every strand kernel: SG_STRANDS logical sub-groups per work-group. */
#if defined(SG_INTEL_REQD_SIZE) && SG_INTEL_REQD_SIZE
#define SG_KERNEL_ATTRS                                      \
  __attribute__((reqd_work_group_size(SG_GROUP_SIZE, 1, 1))) \
  __attribute__((intel_reqd_sub_group_size(SG_SIZE)))
#else
#define SG_KERNEL_ATTRS __attribute__((reqd_work_group_size(SG_GROUP_SIZE, 1, 1)))
#endif

/* Per-strand scratch shared by the lanes of a strand: __local with several lanes, private
 * with one (then nothing else can see it and sg_barrier() has nothing to order). */
#if SG_SIZE == 1
#define SG_SHARED
#define sg_barrier() ((void)0)
#else
#define SG_SHARED __local
#define sg_barrier() barrier(CLK_LOCAL_MEM_FENCE)
#endif

typedef struct {
  __local uint4* buf; /* 2 * SG_SIZE entries, only used by the __local backend */
  uint phase;
} sg_ctx;

#if SG_BACKEND == SG_BACKEND_LOCAL && SG_SIZE > 1
#define SG_DECLARE(ctx)                       \
  __local uint4 ctx##_storage_l[2 * SG_SIZE]; \
  sg_ctx ctx;                                 \
  ctx.buf = ctx##_storage_l;                  \
  ctx.phase = 0u
#else
#define SG_DECLARE(ctx) \
  sg_ctx ctx;           \
  ctx.buf = 0;          \
  ctx.phase = 0u
#endif

static inline uint sg_lane(void) { return SG_SIZE == 1 ? 0u : (uint)get_local_id(0) % SG_SIZE; }
/* the strand slot of this work-item within its work-group */
static inline uint sg_slot(void) { return SG_STRANDS == 1 ? 0u : (uint)get_local_id(0) / SG_SIZE; }
/* the strand (draw index) of this work-item: `base` plus its group's strands before it */
static inline uint sg_strand_index(uint base) {
  return base + (uint)get_group_id(0) * (uint)SG_STRANDS + sg_slot();
}
/* strands per launched work-group, for persistent loops */
#define SG_STRAND_STRIDE(groups) ((groups) * (uint)SG_STRANDS)

#if SG_BACKEND == SG_BACKEND_SINGLE || SG_SIZE == 1

/* One lane: nobody to exchange with, every edge result is the fill value. */
static inline uint sg_shuffle_up1(sg_ctx* c, uint x, uint fill) {
  (void)c;
  (void)x;
  return fill;
}
static inline uint sg_shuffle_down1(sg_ctx* c, uint x, uint fill) {
  return sg_shuffle_up1(c, x, fill);
}
static inline uint sg_broadcast0(sg_ctx* c, uint x) {
  (void)c;
  return x;
}
static inline uint4 sg_shuffle_up1_u4(sg_ctx* c, uint4 x, uint4 fill) {
  (void)c;
  (void)x;
  return fill;
}
static inline uint4 sg_shuffle_down1_u4(sg_ctx* c, uint4 x, uint4 fill) {
  return sg_shuffle_up1_u4(c, x, fill);
}

#elif SG_BACKEND == SG_BACKEND_LOCAL

/* Writes x, waits once, reads lane `src` (when it exists) from the current half. */
static inline uint4 sg_local_exchange(sg_ctx* c, uint4 x, int src, uint4 fill) {
  __local uint4* slot_l = c->buf + c->phase * SG_SIZE;
  c->phase ^= 1u;
  slot_l[sg_lane()] = x;
  barrier(CLK_LOCAL_MEM_FENCE);
  return (src >= 0 && src < SG_SIZE) ? slot_l[src] : fill;
}

static inline uint4 sg_shuffle_up1_u4(sg_ctx* c, uint4 x, uint4 fill) {
  return sg_local_exchange(c, x, (int)sg_lane() - 1, fill);
}
static inline uint4 sg_shuffle_down1_u4(sg_ctx* c, uint4 x, uint4 fill) {
  return sg_local_exchange(c, x, (int)sg_lane() + 1, fill);
}
static inline uint sg_shuffle_up1(sg_ctx* c, uint x, uint fill) {
  return sg_shuffle_up1_u4(c, (uint4)(x, 0u, 0u, 0u), (uint4)(fill, 0u, 0u, 0u)).x;
}
static inline uint sg_shuffle_down1(sg_ctx* c, uint x, uint fill) {
  return sg_shuffle_down1_u4(c, (uint4)(x, 0u, 0u, 0u), (uint4)(fill, 0u, 0u, 0u)).x;
}
static inline uint sg_broadcast0(sg_ctx* c, uint x) {
  return sg_local_exchange(c, (uint4)(x, 0u, 0u, 0u), 0, (uint4)(0u)).x;
}

#else /* native backends: 32-bit primitives, wider types by component */

#if SG_BACKEND == SG_BACKEND_KHR
static inline uint sg_raw_up1(uint x) { return sub_group_shuffle_up(x, 1u); }
static inline uint sg_raw_down1(uint x) { return sub_group_shuffle_down(x, 1u); }
static inline uint sg_raw_bcast0(uint x) { return sub_group_broadcast(x, 0u); }

#elif SG_BACKEND == SG_BACKEND_INTEL
static inline uint sg_raw_up1(uint x) { return intel_sub_group_shuffle_up(x, x, 1u); }
static inline uint sg_raw_down1(uint x) { return intel_sub_group_shuffle_down(x, x, 1u); }
static inline uint sg_raw_bcast0(uint x) { return intel_sub_group_shuffle(x, 0u); }

#elif SG_BACKEND == SG_BACKEND_NVPTX
/* NVIDIA's OpenCL exposes no sub-group extension; a 32-lane work-group is one warp. */
#if defined(SG_PTX_LEGACY_SHFL) && SG_PTX_LEGACY_SHFL
static inline uint sg_raw_up1(uint x) {
  uint r;
  __asm__ volatile("shfl.up.b32 %0, %1, 1, 0;" : "=r"(r) : "r"(x));
  return r;
}
static inline uint sg_raw_down1(uint x) {
  uint r;
  __asm__ volatile("shfl.down.b32 %0, %1, 1, 31;" : "=r"(r) : "r"(x));
  return r;
}
static inline uint sg_raw_bcast0(uint x) {
  uint r;
  __asm__ volatile("shfl.idx.b32 %0, %1, 0, 31;" : "=r"(r) : "r"(x));
  return r;
}
#else
static inline uint sg_raw_up1(uint x) {
  uint r;
  __asm__ volatile("shfl.sync.up.b32 %0, %1, 1, 0, 0xffffffff;" : "=r"(r) : "r"(x));
  return r;
}
static inline uint sg_raw_down1(uint x) {
  uint r;
  __asm__ volatile("shfl.sync.down.b32 %0, %1, 1, 31, 0xffffffff;" : "=r"(r) : "r"(x));
  return r;
}
static inline uint sg_raw_bcast0(uint x) {
  uint r;
  __asm__ volatile("shfl.sync.idx.b32 %0, %1, 0, 31, 0xffffffff;" : "=r"(r) : "r"(x));
  return r;
}
#endif

#elif SG_BACKEND == SG_BACKEND_AMD
/* ds_bpermute addresses lanes of the hardware wave in bytes; mbcnt gives the wave lane. */
static inline int sg_amd_hw_lane(void) {
  return (int)__builtin_amdgcn_mbcnt_hi(~0u, __builtin_amdgcn_mbcnt_lo(~0u, 0u));
}
static inline uint sg_raw_up1(uint x) {
  return (uint)__builtin_amdgcn_ds_bpermute((sg_amd_hw_lane() - 1) << 2, (int)x);
}
static inline uint sg_raw_down1(uint x) {
  return (uint)__builtin_amdgcn_ds_bpermute((sg_amd_hw_lane() + 1) << 2, (int)x);
}
static inline uint sg_raw_bcast0(uint x) {
  return (uint)__builtin_amdgcn_ds_bpermute((sg_amd_hw_lane() - (int)sg_lane()) << 2, (int)x);
}

#else
#error "unknown SG_BACKEND"
#endif

static inline uint sg_shuffle_up1(sg_ctx* c, uint x, uint fill) {
  (void)c;
  uint r = sg_raw_up1(x);
  return sg_lane() == 0u ? fill : r;
}
static inline uint sg_shuffle_down1(sg_ctx* c, uint x, uint fill) {
  (void)c;
  uint r = sg_raw_down1(x);
  return sg_lane() == (uint)(SG_SIZE - 1) ? fill : r;
}
static inline uint sg_broadcast0(sg_ctx* c, uint x) {
  (void)c;
  return sg_raw_bcast0(x);
}
static inline uint4 sg_shuffle_up1_u4(sg_ctx* c, uint4 x, uint4 fill) {
  return (uint4)(sg_shuffle_up1(c, x.x, fill.x), sg_shuffle_up1(c, x.y, fill.y),
                 sg_shuffle_up1(c, x.z, fill.z), sg_shuffle_up1(c, x.w, fill.w));
}
static inline uint4 sg_shuffle_down1_u4(sg_ctx* c, uint4 x, uint4 fill) {
  return (uint4)(sg_shuffle_down1(c, x.x, fill.x), sg_shuffle_down1(c, x.y, fill.y),
                 sg_shuffle_down1(c, x.z, fill.z), sg_shuffle_down1(c, x.w, fill.w));
}

#endif /* backends */

static inline float4 sg_shuffle_up1_f4(sg_ctx* c, float4 x, float4 fill) {
  return as_float4(sg_shuffle_up1_u4(c, as_uint4(x), as_uint4(fill)));
}
static inline float4 sg_shuffle_down1_f4(sg_ctx* c, float4 x, float4 fill) {
  return as_float4(sg_shuffle_down1_u4(c, as_uint4(x), as_uint4(fill)));
}

#endif /* CLHAIR_SUBGROUP_H */
