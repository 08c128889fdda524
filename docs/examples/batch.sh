# How-to: skies by the thousand with `skydome batch` (docs/howto/batch.md). Files go to
# $OUT (default ./out).
set -eu
OUT=${OUT:-out}
HERE=$(dirname "$0")

# Check the spec and list its 12 jobs (file stems), rendering nothing.
skydome batch "$HERE/batch_spec.toml" --dry-run

# Render them in this process (--serial; on Dask: --workers N, or --scheduler ADDRESS), with
# the manifest in $OUT/batch/manifest.parquet and manifest.csv.
skydome batch "$HERE/batch_spec.toml" --serial -o "$OUT/batch"

# Again: every job is complete (its files match the manifest's checksums), nothing is drawn.
skydome batch "$HERE/batch_spec.toml" --serial -o "$OUT/batch"
