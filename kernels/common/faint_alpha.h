/* faint_alpha.h — the alpha share of a faint groom's widened centre hits (host/io/
 * faint_groom.h): the hits were drawn hit_diameter_px wide, the fibre is faint_width_px1 / z
 * wide, so a pixel they cover holds that fraction of it. 1 for every other groom. */
#ifndef CLH_FAINT_ALPHA_H
#define CLH_FAINT_ALPHA_H

static inline float clh_faint_alpha(__global const ClhGroomGpu* groom_g, float z) {
  if (!(groom_g->faint_width_px1 > 0.0f && groom_g->hit_diameter_px > 0.0f && z > 0.0f))
    return 1.0f;
  return fmin(groom_g->faint_width_px1 / (z * groom_g->hit_diameter_px), 1.0f);
}

#endif
