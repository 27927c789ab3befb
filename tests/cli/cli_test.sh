#!/usr/bin/env bash
# Command-line tests of `facet brdf | reflectance`: values against closed forms and bad input
# against the documented errors (message naming the flag, non-zero exit).
# Usage: cli_test.sh path/to/facet
set -u
facet="$1"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
pass=0
fail=0

# expect_ok NAME REGEX CMD...: exit 0 and stdout matches REGEX
expect_ok() {
  local name="$1" regex="$2"; shift 2
  local out
  if out="$("$@" 2>&1)" && grep -Eq -- "$regex" <<<"$out"; then pass=$((pass + 1))
  else fail=$((fail + 1)); echo "FAIL $name: $*"; echo "$out" | head -5; fi
}
# expect_err NAME REGEX CMD...: exit != 0 and stderr+stdout matches REGEX
expect_err() {
  local name="$1" regex="$2"; shift 2
  local out
  if out="$("$@" 2>&1)"; then fail=$((fail + 1)); echo "FAIL $name: exit 0 for $*"; return; fi
  if grep -Eq -- "$regex" <<<"$out"; then pass=$((pass + 1))
  else fail=$((fail + 1)); echo "FAIL $name: message '$out' does not match '$regex'"; fi
}

# Lambert f = rho/pi = 0.5/pi = 0.159155 (printed to 6 significant digits).
expect_ok lambert-eval '^    0\.1591549' "$facet" brdf eval --model lambert --reflectance 0.5 --wi 10,0 --wo 40,90 --json
expect_ok lambert-eval-text 'f   = 0.159155 0.159155 0.159155' "$facet" brdf eval --model lambert --reflectance 0.5
# Principled with specular 0 and roughness 0 is Disney diffuse without retro-reflection: at
# normal incidence on both sides F_V = F_L = 0, so f = C / pi = 0.5 / pi.
expect_ok principled-eval 'f   = 0.159155 0.159155 0.159155' "$facet" brdf eval --model principled \
  --base_color 0.5 --specular 0 --roughness 0 --wi 0,0 --wo 0,0
# Reflectance of principled (through its sampler): Disney diffuse alone (specular 0, roughness 0)
# at normal incidence, F_V = 0: rho = C (1 - 1/2 * 2 int (1 - mu)^5 mu dmu) = 0.5 (1 - 1/42) =
# 0.488095.
expect_ok principled-reflectance 'rho\(wi->2pi\) at theta_i = 0 deg: 0\.48809[45]' "$facet" \
  reflectance --model principled --base_color 0.5 --specular 0 --roughness 0
# Multiscatter GGX: a white metal reflects everything (the compensation's error is < 3e-3); with
# ggx the same metal reflects 0.57.
expect_ok principled-multi-ggx-furnace 'theta_i = 30 deg: (0\.99[7-9]|1\.00[0-2])' "$facet" \
  reflectance --model principled --base_color 1 --metallic 1 --roughness 0.8 \
  --distribution multi_ggx --theta-i 30
# Transmissive models: reflectance and transmittance apart (directional_scattering). A smooth
# interface of IOR 1.5 at normal incidence: F = 0.04, the rest transmitted (to one of the 2^16
# lobe-choice strata: 2621 / 65536 = 0.0399933).
expect_ok dielectric-scattering 'rho\(wi->same side\) at theta_i = 0 deg: 0\.0(399[89]|400[01])' \
  "$facet" reflectance --model dielectric --ior 1.5 --theta-i 0
expect_ok dielectric-transmittance 'tau\(wi->other side\) at theta_i = 0 deg: 0\.9(599[89]|600[01])' \
  "$facet" reflectance --model dielectric --ior 1.5 --theta-i 0
expect_ok principled-reflectance-transmission 'tau\(wi->other side\)' "$facet" reflectance \
  --model principled --transmission 1
expect_err dielectric-table 'for one incidence only' "$facet" reflectance --model dielectric \
  --table
expect_err principled-distribution '--distribution' "$facet" brdf eval --model principled \
  --distribution beckmann
# Cosine-weighted sampling: pdf = cos(theta)/pi <= 1/pi for every sample.
expect_ok lambert-sample 'diffuse' "$facet" brdf sample --model lambert --count 4 --seed 7
# Mirror: a delta, f = pdf = 0 off the delta; samples are specular with pdf 1.
expect_ok mirror-eval '"pdf": 0' "$facet" brdf eval --model mirror --json
expect_ok mirror-sample '"flags": "specular"' "$facet" brdf sample --model mirror --wo 30,0 --count 1 --json
# Reflectance of a white Lambertian: exactly 1.
# Adaptive default to 1e-6 (the float evaluation of rho/pi leaves 5e-8):
expect_ok reflectance-lambert 'rho\(wi->2pi\) at theta_i = 60 deg: (1\.0000000|0\.9999999)[0-9] ' "$facet" reflectance --model lambert --reflectance 1 --theta-i 60
# GGX alpha 0.2 at 70 deg: 0.8676247 (double-precision reference 0.867624721, tests/core).
expect_ok reflectance-ggx70 'rho\(wi->2pi\) at theta_i = 70 deg: 0\.867624[5-9][0-9] .*estimated quadrature error [0-9.]+e-0[7-9]' "$facet" reflectance --model ggx --theta-i 70
expect_ok reflectance-order 'estimated quadrature error 7\.7e-03' "$facet" reflectance --model ggx --theta-i 70 --order 32
expect_err bad-tolerance '--tolerance: must be in \[1e-9, 0.1\]' "$facet" reflectance --model ggx --tolerance 0
expect_ok reflectance-bihemi 'rho\(2pi->2pi\) = (0\.2500000|0\.2499999)' "$facet" reflectance --model lambert --reflectance 0.25 --bihemispherical
expect_ok reflectance-table 'alpha=0.5' "$facet" reflectance --model ggx --table --thetas 0,60 --sweep alpha=0.1,0.5
expect_ok plot 'wrote' "$facet" brdf plot --model composite --alpha 0.2 -o "$tmp/lobe.png"
[ -s "$tmp/lobe.png" ] && pass=$((pass + 1)) || { fail=$((fail + 1)); echo "FAIL plot: no PNG"; }
expect_ok models-markdown '#### `ggx`' "$facet" brdf models --markdown

# Bad input: the flag is named, the exit code is non-zero.
expect_err unknown-model "--model: unknown model 'lamber' \(did you mean 'lambert'\?\)" "$facet" brdf eval --model lamber
expect_err unknown-param "--alpah: unknown parameter 'alpah' for model 'ggx' \(did you mean 'alpha'\?\)" "$facet" brdf eval --model ggx --alpah 0.3
expect_err negative-alpha "--alpha: parameter 'alpha' of model 'ggx': must be in \[0, 10\]" "$facet" brdf eval --model ggx --alpha -1
expect_err rho-range "--reflectance: parameter 'reflectance' of model 'lambert': must be in \[0, 1\]" "$facet" brdf eval --model lambert --reflectance 1.5
expect_err nan "--alpha: 'nan' is not a finite number" "$facet" brdf eval --model ggx --alpha nan
expect_err bad-direction "--wi: theta must be in \[0, 90\]" "$facet" brdf eval --model lambert --wi 120,0
expect_err bad-direction-format "--wo: expected theta,phi" "$facet" brdf eval --model lambert --wo 30
expect_err missing-model "model is required|--model is required" "$facet" brdf eval
expect_err bad-count "--count: must be in" "$facet" brdf sample --model lambert --count 0
expect_err bad-cone "--cone-in: half_angle must be in" "$facet" reflectance --model lambert --cone-in 0,0,0 --cone-out 0,0,10

# The docs read the model table: docs/models.md holds exactly what `facet brdf models --markdown`
# prints, between its markers (every model unit appears there).
doc="$(dirname "$0")/../../docs/models.md"
"$facet" brdf models --markdown > "$tmp/models.md"
sed -n '/^<!-- generated by `facet brdf models --markdown`: begin -->$/,/^<!-- generated: end -->$/p' "$doc" \
  | sed '1d;$d' > "$tmp/doc_models.md"
if diff -q "$tmp/models.md" "$tmp/doc_models.md" > /dev/null; then pass=$((pass + 1))
else fail=$((fail + 1)); echo "FAIL docs/models.md differs from facet brdf models --markdown (regenerate it)"
  diff "$tmp/models.md" "$tmp/doc_models.md" | head -10; fi

echo "cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
