# Virtex-II synthesis of one rheo RTL design. Driven by environment variables so that
# `rheo synth` (host/synth/) and a person at a shell run exactly the same flow:
#   RHEO_RTL_DIR   folder holding the .sv sources (rtl/)
#   RHEO_SOURCES   space-separated file names inside RHEO_RTL_DIR, package first
#   RHEO_TOP       top module (rheo_tem, rheo_mpm, the core top)
#   RHEO_PARAMS    optional "Name=Value ..." overrides of the top's parameters
#   RHEO_OUT       output prefix: writes $RHEO_OUT.stat.json, .ltp.txt, .cells.txt, .edif,
#                  .netlist.json
# Usage: RHEO_RTL_DIR=rtl RHEO_SOURCES="rheo_consts_pkg.sv rheo_operand.sv rheo_rsqrt.sv rheo_tem.sv" \
#        RHEO_TOP=rheo_tem RHEO_OUT=/tmp/tem yosys -q -c scripts/synth.tcl
yosys -import

set rtl_dir $::env(RHEO_RTL_DIR)
set top $::env(RHEO_TOP)
set out $::env(RHEO_OUT)
set params ""
if {[info exists ::env(RHEO_PARAMS)]} { set params $::env(RHEO_PARAMS) }

foreach src $::env(RHEO_SOURCES) { read_verilog -sv $rtl_dir/$src }

# Parameters are set on the parsed top before elaboration (chparam, then hierarchy);
# `hierarchy -chparam` trips an internal assertion of Yosys 0.23 on the core.
if {[llength $params] > 0} {
  set chparam_args {}
  foreach assignment $params {
    set kv [split $assignment =]
    lappend chparam_args -set [lindex $kv 0] [lindex $kv 1]
  }
  chparam {*}$chparam_args $top
}
hierarchy -top $top
# chparam derives "$paramod\<top>\..."; give the top its plain name back for synth_xilinx.
yosys rename -top $top

# -flatten: one netlist, so the longest path crosses module boundaries.
# -ise: netlist conventions ISE expects (inverters as INV cells).
# -noiopad: the cores are placed inside a larger design, not wired to package pins.
synth_xilinx -family xc2v -top $top -flatten -ise -noiopad

tee -q -o $out.stat.json stat -json -tech xilinx
# Register-to-register path: flip-flops and block RAMs end a path, so they are left out
# of the selection ltp walks (ltp -noff only knows Yosys' internal $dff cells).
tee -q -o $out.ltp.txt ltp * t:FD* %d t:RAMB16* %d
# Cell name -> type for every combinational cell type that can lie on that path, so the
# delay model can price each hop.
set fh [open $out.cells.txt w]
foreach type {LUT1 LUT2 LUT3 LUT4 MUXCY XORCY MUXF5 MUXF6 MUXF7 MUXF8 MULT18X18 INV} {
  tee -q -o $out.sel.tmp select -list t:$type
  set sel [open $out.sel.tmp r]
  while {[gets $sel line] >= 0} {
    if {$line ne ""} { puts $fh "$type $line" }
  }
  close $sel
}
close $fh
file delete $out.sel.tmp
write_edif -pvector bra $out.edif
# The mapped netlist for the static timing of host/synth/static_timing.cpp (every
# register-to-register path priced by the delay model, not only the one ltp picks).
write_json $out.netlist.json
