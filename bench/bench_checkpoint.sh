#!/bin/sh
# Checkpoint cost on the 32,000-atom EAM bench (bench/cases/md_eam_32k.yaml):
# one checkpoint every 50 steps (three in 200 steps), timed by the solver's
# own "checkpoint" timer.  Prints the write time per million particles, the
# file size per particle, and what a checkpoint every 1000 steps would add
# to the run time (target: under 2 %).
#   env: BIN ROOT WORK REPEAT (from bench.sh)
set -eu
. "$ROOT/bench/lib.sh"
natoms=32000; steps=200
sed 's/^output: .*/output: {thermo_every: 100, hdf5: false, checkpoint_every: 50}/' \
    "$ROOT/bench/cases/md_eam_32k.yaml" > "$WORK/ckpt.yaml"
: > "$WORK/ckpt.ms"; : > "$WORK/ckpt.step"; : > "$WORK/ckpt.bytes"
i=0
while [ $i -lt "$REPEAT" ]; do
    i=$((i + 1))
    out="$WORK/ckpt$i"
    "$BIN/cascade-solver" run "$WORK/ckpt.yaml" --out "$out" --threads 1 --quiet --no-progress
    t=$(tr -d ' \n' < "$out/result.json")
    ck=$(echo "$t" | grep -o '"checkpoint":{"calls":[0-9]*,"seconds":[0-9.eE+-]*')
    calls=$(echo "$ck" | sed 's/.*"calls":\([0-9]*\).*/\1/')
    secs=$(echo "$ck" | sed 's/.*"seconds"://')
    loop=$(echo "$t" | grep -o '"loop":{"calls":[0-9]*,"seconds":[0-9.eE+-]*' | sed 's/.*"seconds"://')
    echo "$secs * 1000 / $calls" | bc -l >> "$WORK/ckpt.ms"
    echo "($loop - $secs) * 1000 / $steps" | bc -l >> "$WORK/ckpt.step"
    stat -c %s "$out"/checkpoint-*.h5 | tail -n1 >> "$WORK/ckpt.bytes"
done
ms=$(median < "$WORK/ckpt.ms")
step_ms=$(median < "$WORK/ckpt.step")
bytes=$(median < "$WORK/ckpt.bytes")
bench_line checkpoint_write_ms_per_million_particles "$(echo "$ms * 1000000 / $natoms" | bc -l | xargs printf '%.1f')" ms "one checkpoint of the 32,000-atom run, scaled"
bench_line checkpoint_bytes_per_particle "$(echo "$bytes / $natoms" | bc -l | xargs printf '%.1f')" B "HDF5 file size / particles"
bench_line checkpoint_every_1000_steps_overhead "$(echo "100 * $ms / (1000 * $step_ms)" | bc -l | xargs printf '%.3f')" % "target 2"
