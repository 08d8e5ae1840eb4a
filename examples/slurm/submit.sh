#!/bin/bash
# The array, then the merge once every task ended well (afterok).
set -euo pipefail
cd "$(dirname "$0")/../.."
mkdir -p logs
array=$(sbatch --parsable examples/slurm/sweep.sbatch)
sbatch --dependency=afterok:"$array" examples/slurm/merge.sbatch
echo "array $array; merge waits for it"
