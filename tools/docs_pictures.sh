#!/usr/bin/env bash
# Rebuilds every picture in docs/ from this tree, so none shows what the code no longer draws:
# each is a sheet of a shipped matrix's run, a montage of a run's cells (examples/docs_montage.rs:
# README's docs/default-run.png from the main job, Fig 3.10, the composite room), or the main
# job's viewer in headless Chromium (docs/viewer.png).
#   bash tools/docs_pictures.sh [WORK_FOLDER]   (default target/docs-pictures; ~15 min on 2 cores)
# tests/e2e/docs.rs checks that every PNG under docs/ is written here.
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-target/docs-pictures}
mkdir -p "$work"
work=$(realpath "$work")
cargo build --release --bin shadematrix --example docs_montage
bin=${CARGO_TARGET_DIR:-target}/release/shadematrix
montage=${CARGO_TARGET_DIR:-target}/release/examples/docs_montage

# run NAME [MATRIX]: a fresh run of MATRIX (the embedded default matrix without one) into $work/NAME.
run() {
  rm -rf "${work:?}/$1"
  "$bin" run ${2:+"$2"} --no-cache --out "$work/$1" > "$work/$1.log" 2>&1
}

# README: the main job; rows the compositions, columns built-in Standard gold, URP Lit gold, HDRP
# Lit gold, URP Lit blue paint.
run main
rows=()
for c in default mitsuba medusa spikes; do
  rows+=("${c}__builtin-forward__standard__gold__*,${c}__urp-forward__lit__gold__*,${c}__hdrp-forward__lit__gold__*,${c}__urp-forward__lit__blue_paint__*")
done
"$montage" "$work/main" docs/default-run.png 144 "${rows[@]}"

# The viewer: URP Lit gold against HDRP Lit gold in the wipe, FLIP overlay at 35 %.
view="a.composition=default&b.composition=default&a.pipeline=urp&b.pipeline=hdrp&a.shader=lit&b.shader=lit"
view+="&a.preset=gold&b.preset=gold&mode=wipe&overlay=flip&opacity=0.35&wipe=0.5&zoom=1"
profile=$(mktemp -d)
chromium --headless --no-sandbox --disable-gpu --disable-background-networking --disable-component-update \
  --disable-sync --no-first-run --user-data-dir="$profile" --hide-scrollbars --window-size=1300,700 \
  --virtual-time-budget=8000 --screenshot="$PWD/docs/viewer.png" "file://$work/main/index.html#$view" \
  > "$work/viewer.log" 2>&1
rm -rf "$profile"

run surfaces matrices/surfaces.toml
cp "$work/surfaces/sheets/pipeline_x_surface__0.35.png" docs/surfaces.png
run fig2_3 matrices/fig2_3.toml
cp "$work/fig2_3/sheets/pipeline_x_term__phong.png" docs/fig2_3.png
run fig3_5 matrices/fig3_5.toml
cp "$work/fig3_5/sheets/pipeline_x_term__gold_1.00_0.90.png" docs/fig3_5.png
run fig3_2 matrices/fig3_2.toml
cp "$work/fig3_2/sheets/pipeline_x_preset__area_rect.png" docs/fig3_2.png
cp "$work/fig3_2/sheets/pipeline_x_preset__area_three.png" docs/fig3_3.png
# HDRP Lit's material types on gold with the clear coat: a row per type, smoothness 0.25 → 0.9.
run hdrp_materials matrices/hdrp_materials.toml
rows=()
for t in standard specular_color iridescence anisotropy translucent subsurface_scattering; do
  row=""
  for s in 0.25 0.50 0.75 0.90; do row+="${row:+,}default__hdrp-forward__lit__gold__m1.00_s${s}_*coat_mask1_${t}"; done
  rows+=("$row")
done
"$montage" "$work/hdrp_materials" docs/hdrp_materials.png 144 "${rows[@]}"
# HDRP's subsurface scattering on a 2 cm brick-coloured bead: Translucent above, Subsurface
# Scattering below, subsurface mask 0 → 1 across.
run hdrp_subsurface matrices/hdrp_subsurface.toml
cp "$work/hdrp_subsurface/sheets/material_type_x_params__brick_0.10.png" docs/hdrp_subsurface.png

# HDRP's light settings: a row per scene (cone, pyramid, box, range off, diffuse only, specular
# only, shadow dimmer, shadow tint, penumbra tint), columns URP Lit plastic (the plain cone: URP has
# none of them), HDRP Lit plastic and gold.
run hdrp_lights matrices/hdrp_lights.toml
rows=()
for c in cone pyramid box range_off diffuse_only specular_only shadow_dimmer shadow_tint penumbra_tint; do
  rows+=("hdrp_light_${c}__urp-forward__lit__plastic__*,hdrp_light_${c}__hdrp-forward__lit__plastic__*,hdrp_light_${c}__hdrp-forward__lit__gold__*")
done
"$montage" "$work/hdrp_lights" docs/hdrp_lights.png 112 "${rows[@]}"

# Fig 3.10: gold, a metallic-workflow then a specular-workflow row per pipeline, metallic 0 → 1.
run fig3_10 matrices/fig3_10.toml
rows=()
for p in builtin-forward__standard urp-forward__lit hdrp-forward__lit; do
  for setup in 0 1; do
    row=""
    for m in 0.00 0.25 0.50 0.75 1.00; do row+="${row:+,}default__${p}__gold__m${m}_*_specular_setup${setup}"; done
    rows+=("$row")
  done
done
"$montage" "$work/fig3_10" docs/fig3_10.png 96 "${rows[@]}"

# The composite room: rows gold, plastic, blue paint; columns built-in Standard, URP Lit, HDRP Lit.
run composite matrices/composite.toml
rows=()
for preset in gold plastic blue_paint; do
  rows+=("composite__builtin-forward__standard__${preset}__*,composite__urp-forward__lit__${preset}__*,composite__hdrp-forward__lit__${preset}__*")
done
"$montage" "$work/composite" docs/composite.png 240 "${rows[@]}"
# Quality settings: the composite room's gold vase, a row per pipeline from its cheapest settings
# to its own (built-in's quality levels Very Low, Medium, High, Ultra; URP's default asset, its
# 1024 map, its soft shadows, High Fidelity; HDRP all low with SSAO off, its defaults, High
# filtering (PCSS), every level High: PCSS, bloom and full-resolution SSAO); and each pipeline's
# tiers plot, stacked.
run quality matrices/quality.toml
q=composite__builtin-forward__standard__gold__m1.00_s0.90_i1.5_r6
u=composite__urp-forward__lit__gold__m1.00_s0.90_i1.5_r6
h=composite__hdrp-forward__lit__gold__m1.00_s0.90_i1.5_r6
"$montage" "$work/quality" docs/quality.png 160 \
  "${q}_quality_level.very_low,${q}_quality_level.medium,${q}_quality_level.high,${q}" \
  "${u},${u}_main_light_shadow_resolution.1024,${u}_soft_shadows.on,${u}_asset.high_fidelity" \
  "${h}_bloom_quality.low_shadow_filtering.low_shadow_resolution.256_ssao.off,${h},${h}_shadow_filtering.high,${h}_bloom_quality.high_shadow_filtering.high_ssao_quality.high"
printf '<html><body style="margin:0">%s</body></html>' \
  "$(for p in builtin urp hdrp; do printf '<img src="quality/plots/quality_%s.svg"><br>' "$p"; done)" \
  > "$work/quality_plots.html"
profile=$(mktemp -d)
chromium --headless --no-sandbox --disable-gpu --disable-background-networking --disable-component-update \
  --disable-sync --no-first-run --user-data-dir="$profile" --hide-scrollbars --window-size=780,1448 \
  --screenshot="$PWD/docs/quality_plots.png" "file://$work/quality_plots.html" > "$work/quality_plots.log" 2>&1
rm -rf "$profile"
echo "docs pictures rebuilt from $(git rev-parse --short HEAD) (work in $work)"
