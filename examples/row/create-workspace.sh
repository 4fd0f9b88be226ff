#!/usr/bin/env bash
# Makes the row workspace of one threshold study in the current project
# (the directory holding workflow.toml): SHARDS directories
# workspace/STUDY-0 ... whose value.json holds the study's parameters, the
# label STUDY and the directory's shard, e.g.
#
#   create-workspace.sh g23 32 gamma=23 'boxes=[5,6,7,8,10,12]' sequences=2000
#
# A VALUE is written as JSON when it is a number, an array or true/false,
# as a string otherwise (kind=contact). Run again, it leaves the directories
# as they are; a directory whose value would change is refused, since a row
# directory's value never changes.
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 STUDY SHARDS KEY=VALUE..." >&2
    exit 2
fi
study=$1 shards=$2
shift 2
if ! [[ $shards =~ ^[1-9][0-9]*$ ]]; then
    echo "$0: SHARDS must be a positive whole number, not '$shards'" >&2
    exit 2
fi
fields=""
for pair in "$@"; do
    key=${pair%%=*} value=${pair#*=}
    if [ "$key" = "$pair" ] || [ -z "$key" ]; then
        echo "$0: expected KEY=VALUE, not '$pair'" >&2
        exit 2
    fi
    if ! [[ $value =~ ^(-?[0-9.eE+-]+|\[.*\]|true|false)$ ]]; then
        value="\"$value\""
    fi
    fields+="\"$key\": $value, "
done
for ((i = 0; i < shards; i++)); do
    dir=workspace/$study-$i
    value="{\"study\": \"$study\", $fields\"shard\": \"$i/$shards\"}"
    if [ -e "$dir/value.json" ]; then
        if [ "$(cat "$dir/value.json")" != "$value" ]; then
            echo "$0: $dir/value.json holds another value; make a new study" >&2
            exit 2
        fi
        continue
    fi
    mkdir -p "$dir"
    printf '%s\n' "$value" > "$dir/value.json.tmp"
    mv "$dir/value.json.tmp" "$dir/value.json"
done
echo "workspace/$study-0 ... workspace/$study-$((shards - 1)): $shards slices of study $study"
