#!/bin/sh
# Regenerate the pictures of the book (docs/src/images/) from the shipped
# examples: each example is copied to a scratch directory with
# `[output] plot_format = "png"`, run, and the figures named below are copied.
# Run from the repository root:  sh docs/images.sh
# VESELOV names the command (default: `veselov` on PATH). If pngquant is
# installed the pictures are reduced to a palette (they stay under 80 kB).
set -eu
VESELOV=${VESELOV:-veselov}
IMAGES=docs/src/images
SCRATCH=$(mktemp -d)
trap 'rm -rf "$SCRATCH"' EXIT

png_copy() { # example-stem → scenario in $SCRATCH with PNG plots
    sed 's/^\[output\]$/[output]\nplot_format = "png"/' "examples/$1.toml" > "$SCRATCH/$1.toml"
    grep -q '^plot_format' "$SCRATCH/$1.toml" || printf '\n[output]\nplot_format = "png"\n' >> "$SCRATCH/$1.toml"
}
run() { # example-stem
    png_copy "$1"
    "$VESELOV" run "$SCRATCH/$1.toml" --out "$SCRATCH/out/$1" --force --quiet || true
}
keep() { # example-stem figure-stem picture-name
    cp "$SCRATCH/out/$1/$2.png" "$IMAGES/$3.png"
    if command -v pngquant >/dev/null 2>&1; then
        pngquant --force --skip-if-larger --quality=60-90 --speed 1 --strip --output "$IMAGES/$3.png" "$IMAGES/$3.png" || true
    fi
}

run kepler;                 keep kepler energy_error kepler_energy_error
run kepler_custom;          keep kepler_custom momentum_error kepler_custom_momentum_error
run damped_kepler;          keep damped_kepler orbit damped_kepler_orbit
                            keep damped_kepler energy_balance damped_kepler_energy_balance
png_copy van_der_pol
"$VESELOV" verify "$SCRATCH/van_der_pol.toml" --dt 0.1,0.05,0.025,0.0125,0.00625 \
    --out "$SCRATCH/out/van_der_pol_verify" --force --quiet
"$VESELOV" plot "$SCRATCH/out/van_der_pol_verify" --format png > /dev/null
                            keep van_der_pol_verify convergence van_der_pol_convergence
run kepler_sem;             keep kepler_sem energy_error kepler_sem_energy_error
run heavy_top;              keep heavy_top body_momentum heavy_top_body_momentum
run rigid_body_se3;         keep rigid_body_se3 momentum_error rigid_body_se3_momentum_error
run sine_gordon;            keep sine_gordon spacetime sine_gordon_spacetime
                            keep sine_gordon energy_error sine_gordon_energy_error
run sine_gordon_2d;         keep sine_gordon_2d field_2 sine_gordon_2d_field
run klein_gordon_complex;   keep klein_gordon_complex spacetime klein_gordon_complex_spacetime
run beam_free_free;         keep beam_free_free momentum beam_free_free_momentum
run beam_cantilever_damped; keep beam_cantilever_damped centerline_yz beam_cantilever_damped_centerline
run rod_cantilever_centred; keep rod_cantilever_centred energy rod_cantilever_centred_energy
run rod_free_tumbling;      keep rod_free_tumbling momentum rod_free_tumbling_momentum
ls -l "$IMAGES"
