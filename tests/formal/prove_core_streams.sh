#!/bin/sh
# Formal proof of rheo_core's stream ports and FSM invariants (the assertions of
# rtl/rheo_stream_checker.sv, with the input port's rule as an assumption on the
# environment): a bounded check from reset, then temporal induction, which makes the
# proof hold for every clock. Yosys writes SMT-LIBv2 and yosys-smtbmc runs z3.
#
# The core is elaborated with small memories and its datapath modules (TEM, MPM, force
# accumulators, memories) become cut points: their outputs are free values at every clock.
# The properties then hold whatever those modules compute, and the solver only sees the
# core's own logic (the controller rheo_core_ctrl with its FSM, counters, handshake and
# output registers; the crossbar, read-back and plate force paths). The memory modules
# rheo_core_mem_* keep only their address and write-enable decoding once the memories
# inside them are cut. The whole core with its pipelines is beyond z3 here (one lane, 4
# particles, 4 edge slots: 54 s to reach clock 9 of the bounded check, over a minute per
# clock after it, and the first induction step unfinished after 3 minutes).
#
# Usage: prove_core_streams.sh WORK_DIR "LANES..." FILE...
#   FILE...: the core's sources in elaboration order (the CORE list of rtl/sources.cmake,
#   which tests/formal/CMakeLists.txt passes), e.g. "1 2 3" for LANES.
# Exits non-zero when a property fails (yosys-smtbmc prints the failing assertion).
set -eu
work=$1
lanes=$2
shift 2
files="$*"
[ -n "$files" ] || { echo "usage: $0 WORK_DIR LANES FILE..." >&2; exit 2; }
bmc_depth=12      # from reset: past the 4-particle clear, a STATUS command and its words
induction_depth=6

mkdir -p "$work"

for l in $lanes; do
  smt="$work/rheo_core_l$l.smt2"
  # -nosynthesis: the checker is instantiated under `ifndef SYNTHESIS; -formal defines
  # FORMAL, which turns the input port's rule into an assumption and starts in reset.
  yosys -q -l "$work/yosys_l$l.log" -p "
    read_verilog -sv -formal -nosynthesis $files
    chparam -set Lanes $l -set MaxParticles 4 -set MaxEdges 8 -set MaxMaterials 2 rheo_core
    prep -top rheo_core
    cutpoint \$paramod*rheo_tem \$paramod*rheo_mpm \$paramod*rheo_force_acc \
             \$paramod*rheo_ram_sdp \$paramod*rheo_ram_tdp
    flatten
    opt_clean
    memory_map
    opt -fast
    async2sync
    dffunmap
    write_smt2 -wires $smt
  " >/dev/null
  grep -q '\$assert' "$work/yosys_l$l.log" || { echo "no assertions elaborated" >&2; exit 1; }
  # --unroll: z3 4.8 stalls on the nested define-fun of the state functions otherwise.
  echo "== lanes $l: bounded check, $bmc_depth clocks from reset"
  yosys-smtbmc -s z3 --unroll --noprogress -t $bmc_depth "$smt"
  echo "== lanes $l: temporal induction, depth $induction_depth"
  yosys-smtbmc -s z3 --unroll --noprogress -i -t $induction_depth "$smt"
done
echo "rheo_core stream properties proved for lanes: $lanes"
