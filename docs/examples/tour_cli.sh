# Quick tour: the command line. Files go to $OUT (default ./out).
set -eu
OUT=${OUT:-out}
mkdir -p "$OUT"

skydome places valletta                      # the built-in gazetteer
skydome render --place Valletta --time 2018-03-01T16:52Z --look sun --fov 60 \
    --size 320x180 -o "$OUT/cli-sunset.png" -o "$OUT/cli-sunset.exr"
skydome render --sun-elevation 8 --sun-azimuth 250 --size 320x180 -o "$OUT/cli-sun8.png"
skydome illuminance --sun-elevation 30 --json  # lx on the ground, zenith cd/m^2
skydome ephemeris --lat 35.9 --lon 14.51 --time 2018-03-01T19:00:00Z --bodies sun,moon,sirius
skydome events --lat 35.9 --lon 14.51 --date 2018-03-01
