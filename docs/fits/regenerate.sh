#!/bin/sh
# Regenerates the albedo sweeps of docs/christensen_burley.md: normalized_diffusion's scaling
# factor s fitted at each albedo (configuration 3: l = mean free path, 4: l = diffuse mean free
# path), and the paper's own curves (configurations 0 and 2, S unused: rel_err_start is theirs),
# at eta 1.0, 1.3 and 1.4. Run from the repository root after building:
#   sh docs/fits/regenerate.sh [path/to/bssrdf-workbench]
set -e
exe=${1:-build/app/bssrdf-workbench}
albedos=0.3,0.5,0.7,0.8,0.9,0.95,0.98,0.99,0.995,0.998,0.999
for eta in 1.0 1.3 1.4; do
  "$exe" fit --model materials/normalized_diffusion.bssrdf --set Configuration=3 --params S \
    --albedo-sweep $albedos --eta $eta --paths 1000000 \
    --published docs/fits/christensen_burley_searchlight_mfp.csv --out docs/fits/mfp_eta$eta
  "$exe" fit --model materials/normalized_diffusion.bssrdf --set Configuration=4 --params S \
    --albedo-sweep $albedos --eta $eta --paths 1000000 \
    --published docs/fits/christensen_burley_searchlight_dmfp.csv --out docs/fits/dmfp_eta$eta
  for c in 0 2; do
    "$exe" fit --model materials/normalized_diffusion.bssrdf --set Configuration=$c --params S \
      --albedo-sweep $albedos --eta $eta --paths 1000000 --no-uncertainty --no-plots \
      --max-evaluations 20 --out docs/fits/published$c\_eta$eta || test $? = 6
  done
done
