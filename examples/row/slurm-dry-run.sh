#!/bin/bash
#SBATCH --job-name=slice-g23-0
#SBATCH --output=slice-%j.out
#SBATCH --partition=shared
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=4
#SBATCH --mem-per-cpu=1800M
#SBATCH --time=120

directories=(
g23-0
)

export ACTION_WORKSPACE_PATH=workspace
export ACTION_CLUSTER=anvil
export ACTION_NAME=slice
export ACTION_PROCESSES=1
export ACTION_WALLTIME_IN_MINUTES=120
export ACTION_THREADS_PER_PROCESS=4

trap 'printf %s\\n "${directories[@]}" | row scan --no-progress -a slice - || exit 3' EXIT
for directory in "${directories[@]}"
do
    RAYON_NUM_THREADS=$ACTION_THREADS_PER_PROCESS rgc workspace slice --quiet workspace/$directory || { >&2 echo "[ERROR row::action] Error executing command."; exit 2; }
done
