#!/usr/bin/env bash
# Regenerates the generated part of the fuzz seed corpora (run once; the
# output is checked in): copies of the shipped scenes and configs, the
# resolved built-in scene and configs as dumped by raplas, and six tiny
# valid traces (one without pair-less spheres). The OBJ seeds in corpus/fuzz_obj and the regression inputs
# (inputs that once found a bug) are not generated.
# Usage: tests/fuzz/make_corpus.sh [path/to/raplas]   (default: build/raplas)
set -euo pipefail
cd "$(dirname "$0")/../.."
raplas=${1:-build/raplas}
c=tests/fuzz/corpus

for f in scenes/*.toml; do cp "$f" "$c/fuzz_scene/$(basename "$f")"; done
"$raplas" render --dump-scene > "$c/fuzz_scene/dump_builtin.toml"
"$raplas" render --dump-scene --set floor=true --set camera.eye=[1,2,3] --set camera.look_at=[0,0,0] \
  --set light.corner=[0,5,0] --set light.edge_u=[1,0,0] --set light.edge_v=[0,0,1] > "$c/fuzz_scene/dump_all_keys.toml"

for f in configs/*.toml; do cp "$f" "$c/fuzz_config/$(basename "$f")"; done
for cfg in paper fpga; do
  "$raplas" simulate --config "$cfg" --dump-config > "$c/fuzz_config/dump_$cfg.toml"
done

small=(--set image.width=8 --set image.height=8 --set groups.size=4 --set groups.shadow_size=4 -q)
"$raplas" trace "${small[@]}" --set builtin_detail=0 --out "$c/fuzz_trace/builtin_8x8_g4.trace"
"$raplas" trace "${small[@]}" --set builtin_detail=0 --triangle-select both --out "$c/fuzz_trace/builtin_8x8_g4_both.trace"
"$raplas" trace "${small[@]}" --set builtin_detail=0 --set groups.shadow_size=2 \
  --set spheres.triangles_per_sphere=4 --format float64 --out "$c/fuzz_trace/builtin_8x8_g4_f64.trace"
"$raplas" trace "${small[@]}" --mesh "$c/fuzz_obj/quad.obj" --format fp1-8-15-rtz \
  --out "$c/fuzz_trace/quad_8x8_g4_fp24.trace"
"$raplas" trace "${small[@]}" --mesh "$c/fuzz_obj/quad.obj" --format float32-wt \
  --out "$c/fuzz_trace/quad_8x8_g4_wt.trace"
# The fp24 trace with its format named by the explicit (default) rounding
# suffix "-rne" instead of "-rtz", same length, as a version 4 trace (every
# block's checksum FNV-1a, which Python computes without a library): the seed
# of the older format's reader.
python3 - "$c/fuzz_trace/quad_8x8_g4_fp24.trace" "$c/fuzz_trace/format_name_rne.trace" <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
i = b.index(b"fp1-8-15-rtz")
b[i:i + 12] = b"fp1-8-15-rne"
struct.pack_into("<I", b, 8, 4)
# the blocks after the 32-byte file header: kind u32, size u64, checksum u64, payload
at = 32
while at < len(b):
    size = struct.unpack_from("<Q", b, at + 4)[0]
    h = 1469598103934665603
    for x in b[at + 20:at + 20 + size]:
        h = ((h ^ x) * 0x100000001b3) & 0xffffffffffffffff
    struct.pack_into("<Q", b, at + 12, h)
    at += 20 + size
open(sys.argv[2], "wb").write(b)
PY
for f in "$c"/*/*; do
  size=$(stat -c %s "$f")
  if ((size >= 65536)); then echo "$f: $size bytes, seeds must stay under 64 KB" >&2; exit 1; fi
done
ls -l "$c"/*/
