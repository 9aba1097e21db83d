# cleanslam --dataset streams the dataset: its peak memory on a 1200 s recording of the room is
# within 10 % of that on a 60 s one (a reader that kept the rows needs three times as much).
. "$(dirname "$0")/common.sh"
[ -x /usr/bin/time ] || { echo "SKIP: /usr/bin/time (GNU time) is not installed"; exit 77; }
run "$BIN/cleanslam-sim" default-room "$WORK/short" --set duration_s=60 >/dev/null 2>&1 ||
  fail "cleanslam-sim short"
run "$BIN/cleanslam-sim" default-room "$WORK/long" --set path.repeats=3 --set duration_s=1200 \
  >/dev/null 2>&1 || fail "cleanslam-sim long"
# peak NAME: the run's maximum resident set size, KB
peak() {
  /usr/bin/time -f %M -o "$WORK/$1.rss" $EMU "$BIN/cleanslam" --dataset "$WORK/$1" \
    --tum "$WORK/$1.tum" >/dev/null 2>"$WORK/$1.err" || { cat "$WORK/$1.err" >&2; fail "run $1"; }
  tail -n 1 "$WORK/$1.rss"
}
short=$(peak short)
long=$(peak long)
echo "peak RSS: 60 s dataset $short KB, 1200 s dataset $long KB"
[ $((long * 10)) -le $((short * 11)) ] || fail "peak RSS $long KB on 1200 s, more than 10 % over $short KB on 60 s"
