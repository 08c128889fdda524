# How-to: an HDRI for Blender from the command line. Files go to $OUT (default ./out).
set -eu
OUT=${OUT:-out}
mkdir -p "$OUT"

# An equirect map in cd/m^2, the Sun's disk included (use --size 4096x2048 or more).
skydome render --place Valletta --time 2018-03-01T09:00Z --camera equirect --size 512x256 \
    -o "$OUT/sky.exr" -o "$OUT/sky.hdr" -o "$OUT/sky-preview.png"

# For a scene with a ground of its own, lit by a Sun lamp: no disk, and nothing below the
# horizon (--ground none keeps the air's glow in front of the ground; an albedo sets it).
skydome render --place Valletta --time 2018-03-01T09:00Z --camera equirect --size 512x256 \
    --no-sun-disk --ground black -o "$OUT/sky-black-ground.exr"
