# Sourced by the replay tests: EMU CLEANSLAM REPLAY SIM WORK from the arguments, helpers.
set -eu
EMU=$1
CLEANSLAM=$2
REPLAY=$3
SIM=$4
WORK=$5
. "$(dirname "$0")/../shell/helpers.sh"
# A short simulated run: features-level dataset with faults of the scenario.
simulate() {
  run "$SIM" default-room "$WORK/ds" --set duration_s=20 >"$WORK/sim.log" 2>&1 ||
    { cat "$WORK/sim.log" >&2; fail "cleanslam-sim"; }
}
