# Exposure as the eye or a photographer would choose it, and glare. Files go to $OUT.
set -eu
OUT=${OUT:-out}
mkdir -p "$OUT"

# A moonless night as a dark-adapted eye sees it (the default --metering eye), and as a
# camera's average metering exposes it (bright and tan, the light's physical colour).
skydome render --place Paranal --time 2024-07-05T04:00Z --camera fisheye --size 320x320 \
    -o "$OUT/night-eye.png"
skydome render --place Paranal --time 2024-07-05T04:00Z --camera fisheye --size 320x320 \
    --metering average -o "$OUT/night-camera.png"
# The full Moon close up: centre-weighted metering exposes for the Moon; a lens's glare.
skydome render --place Paranal --time 2024-06-22T04:00Z --look moon --fov 1 --size 320x180 \
    --metering center --glare lens -o "$OUT/moon-center.png"
# The setting Sun with the eye's glare (the default), without, and the EXR: the same frame.
skydome render --place Valletta --time 2018-03-01T16:50Z --look sun --size 320x180 \
    -o "$OUT/sunset-glare.png" -o "$OUT/sunset.exr"
skydome render --place Valletta --time 2018-03-01T16:50Z --look sun --size 320x180 \
    --glare off -o "$OUT/sunset-no-glare.png"
