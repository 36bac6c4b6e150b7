// sampling: BSSRDF importance sampling on the CPU, King et al. 2013 ("BSSRDF Importance
// Sampling", SIGGRAPH 2013 talk). No GL, no ImGui.
//   - radial.h: the per-channel radial distribution pdf_disk(r) ∝ R(r) cut at R_m;
//   - tabulated_radial.h: it for a tabulated profile (exact inversion of the piecewise CDF);
//   - gaussian_lobes.h: it for a sum of planar Gaussians (one-sample MIS over lobes);
//   - inverse_cdf_radial.h: it from an inverse CDF given at knots (a model's analytic sampler);
//   - frame.h, surface.h, analytic_surfaces.h, mesh_surface.h: the shading frame and the
//     geometry probed (sphere, plane, Embree mesh), with uniform area sampling;
//   - disk_sampling.h: probe rays along N, T or B with axis and channel MIS (the estimator and
//     its density are derived there).
#pragma once

#include "sampling/analytic_surfaces.h"
#include "sampling/disk_sampling.h"
#include "sampling/frame.h"
#include "sampling/gaussian_lobes.h"
#include "sampling/inverse_cdf_radial.h"
#include "sampling/mesh_surface.h"
#include "sampling/radial.h"
#include "sampling/surface.h"
#include "sampling/tabulated_radial.h"
