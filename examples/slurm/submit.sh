#!/bin/bash
# Runs a kincal study on a Slurm cluster: a job array of SHARDS tasks (one shard each), then the merge.
#   examples/slurm/submit.sh STUDY.yaml OUT SHARDS [sbatch options for the array, e.g. --time=4:00:00 -c 8]
# Results: OUT/merged/report.md; logs: OUT/logs/shard_<task>.log, OUT/logs/merge.log. KINCAL names the binary
# (default: kincal on PATH). Prints the two job ids on its last line: "array=<id> merge=<id>".
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 STUDY.yaml OUT SHARDS [sbatch options for the array]" >&2
  exit 2
fi
study=$(realpath "$1")
out=$(realpath -m "$2")
shards=$3
shift 3
here=$(dirname "$(realpath "$0")")
kincal=${KINCAL:-$(command -v kincal || true)}
if [ -z "$kincal" ]; then
  echo "$0: kincal is not on PATH; set KINCAL to the binary" >&2
  exit 2
fi
mkdir -p "$out/logs"
array=$(sbatch --parsable --array=1-"$shards" --output="$out/logs/shard_%a.log" \
  --export=ALL,STUDY="$study",OUT="$out",KINCAL="$kincal" "$@" "$here/study_array.sbatch")
array=${array%%;*}
merge=$(sbatch --parsable --dependency=afterok:"$array" --kill-on-invalid-dep=yes --output="$out/logs/merge.log" \
  --export=ALL,OUT="$out",KINCAL="$kincal" "$here/merge.sbatch")
merge=${merge%%;*}
echo "submitted: array job $array ($shards shards) and merge job $merge; report: $out/merged/report.md"
echo "array=$array merge=$merge"
