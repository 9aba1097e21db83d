# Sourced by the tools tests: EMU BIN SRC WORK from the arguments, helpers.
set -eu
EMU=$1
BIN=$2
SRC=$3
WORK=$4
. "$(dirname "$0")/../shell/helpers.sh"
# expect STATUS FILE TEXT COMMAND...: COMMAND exits with STATUS and its stderr (kept in FILE)
# holds TEXT.
expect() {
  want=$1 file=$2 text=$3
  shift 3
  status=0
  run "$@" >"$file.out" 2>"$file" || status=$?
  [ "$status" -eq "$want" ] || { cat "$file" >&2; fail "$* exited $status, expected $want"; }
  grep -qF -- "$text" "$file" || { cat "$file" >&2; fail "$*: no '$text' in its messages"; }
}
# A short feature-level dataset, and a short one with rendered images.
features_dataset() {
  run "$BIN/cleanslam-sim" default-room "$1" --set duration_s=20 >/dev/null 2>&1 ||
    fail "cleanslam-sim $1"
}
images_dataset() {
  run "$BIN/cleanslam-sim" default-room "$1" --set duration_s=6 --set camera.mode=images \
    >/dev/null 2>&1 || fail "cleanslam-sim $1 (images)"
}
