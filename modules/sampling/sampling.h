// sampling: BSSRDF importance sampling on the CPU, King et al. 2013 ("BSSRDF Importance
// Sampling", SIGGRAPH 2013 talk). No GL, no ImGui.
//   - radial.h: the per-channel radial distribution pdf_disk(r) ∝ R(r) cut at R_m;
//   - tabulated_radial.h: it for a tabulated profile (exact inversion of the piecewise CDF);
//   - gaussian_lobes.h: it for a sum of planar Gaussians (one-sample MIS over lobes);
#pragma once

#include "sampling/gaussian_lobes.h"
#include "sampling/radial.h"
#include "sampling/tabulated_radial.h"
