# How-to: a time-lapse with `skydome timelapse`. Files go to $OUT (default ./out).
set -eu
OUT=${OUT:-out}
mkdir -p "$OUT"

# Dusk at Valletta, a frame every 5 minutes, as an H.264 MP4; the exposure follows an eye
# that adapts over time (the default, --exposure adapt).
skydome timelapse --place Valletta --start 2018-03-01T16:30Z --end 2018-03-01T18:30Z \
    --step 5min --size 320x180 --look west --fps 12 -o "$OUT/dusk.mp4"

# The same evening as numbered EXR frames in cd/m^2 (for compositing or grading), all-sky.
skydome timelapse --place Valletta --start 2018-03-01T17:00Z --end 2018-03-01T18:00Z \
    --step 20min --size 160x160 --camera fisheye --format exr -o "$OUT/dusk-frames"

# A fixed exposure instead of the adapting eye: EV100 8 suits the first minutes of dusk.
skydome timelapse --place Valletta --start 2018-03-01T16:50Z --end 2018-03-01T17:10Z \
    --step 10min --size 160x90 --exposure 8 --format png -o "$OUT/dusk-ev8"
