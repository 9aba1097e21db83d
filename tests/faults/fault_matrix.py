#!/usr/bin/env python3
"""Fault matrix: the real programs on small simulated datasets and logs, each mutated with one
fault, and the outcome each fault must have: refused with a message naming what is at fault, or
recovered with the trajectory error within a bound (and told). Prints the table of outcomes.

usage: fault_matrix.py BINDIR WORKDIR [CASE ...]   (native builds: tests/faults/CMakeLists.txt)
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import time
import zlib

INT64_MAX = 2**63 - 1
INT64_MIN = -(2**63)
YEAR_NS = 365 * 86400 * 10**9
TIMEOUT_S = 20  # a run that never ends (a stamp far in the future) is a failure
KILL_ROUNDS = 25  # rounds of two writers killed
BIN = sys.argv[1] if len(sys.argv) > 1 else "build/host-release/bin"
WORK = sys.argv[2] if len(sys.argv) > 2 else "/tmp/fault_matrix"
ONLY = sys.argv[3:]


def run(args, timeout=TIMEOUT_S):
    """(exit code or 'timeout', stderr text, seconds)"""
    t0 = time.monotonic()
    try:
        p = subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                           timeout=timeout)
        return p.returncode, p.stderr.decode(errors="replace"), time.monotonic() - t0
    except subprocess.TimeoutExpired as e:
        return "timeout", (e.stderr or b"").decode(errors="replace"), time.monotonic() - t0


def prog(name):
    return os.path.join(BIN, name)


def simulate(out, seconds, *sets):
    args = [prog("cleanslam-sim"), "default-room", out, "--set", "duration_s=%d" % seconds]
    for s in sets:
        args += ["--set", s]
    code, err, _ = run(args, timeout=120)
    if code != 0:
        sys.exit("cleanslam-sim failed:\n" + err)


def ate(dataset, tum):
    code = subprocess.run([prog("cleanslam-eval"), "--gt",
                           os.path.join(dataset, "groundtruth.csv"), "--est", tum,
                           "--json"], capture_output=True)
    if code.returncode != 0:
        return None
    return json.loads(code.stdout)["ate_rmse_m"]


# --- dataset mutations -------------------------------------------------------------------------

def copy_dataset(src, name):
    dst = os.path.join(WORK, name)
    shutil.rmtree(dst, ignore_errors=True)
    shutil.copytree(src, dst)
    return dst


def edit_csv(folder, file, edit):
    path = os.path.join(folder, file)
    with open(path) as f:
        lines = f.read().splitlines()
    header, rows = lines[0], [r.split(",") for r in lines[1:]]
    rows = edit(rows)
    with open(path, "w") as f:
        f.write("\n".join([header] + [",".join(map(str, r)) for r in rows]) + "\n")


def set_stamp(index, value):
    def edit(rows):
        rows[index][0] = str(value)
        return rows
    return edit


def png_gray(width, height, pixels):
    raw = b"".join(b"\0" + pixels[y * width:(y + 1) * width] for y in range(height))

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def image_files(folder):
    with open(os.path.join(folder, "cam0", "data.csv")) as f:
        return [row.split(",")[1].strip() for row in f.read().splitlines()[1:] if row.strip()]


# --- log mutations -----------------------------------------------------------------------------
# File header 16 bytes; record: sync u32, length u32, type u16, flags u16, crc u32, payload. The
# CRC-32 covers length, type, flags and the payload.
SYNC = 0x52534C43
T_CONFIG, T_CLOCK, T_GYRO, T_ENCODER, T_FRAME = 1, 2, 3, 4, 5


def read_log(path):
    with open(path, "rb") as f:
        data = f.read()
    header, pos, recs = data[:16], 16, []
    while pos + 16 <= len(data):
        sync, length, rtype, flags, crc = struct.unpack_from("<IIHHI", data, pos)
        assert sync == SYNC, "unexpected bytes at %d" % pos
        payload = data[pos + 16:pos + 16 + length]
        assert zlib.crc32(data[pos + 4:pos + 12] + payload) & 0xFFFFFFFF == crc
        recs.append([rtype, flags, bytearray(payload)])
        pos += 16 + length
    return header, recs


def record_bytes(rtype, flags, payload):
    head = struct.pack("<IHH", len(payload), rtype, flags)
    crc = zlib.crc32(head + bytes(payload)) & 0xFFFFFFFF
    return struct.pack("<I", SYNC) + head + struct.pack("<I", crc) + bytes(payload)


def write_log(path, header, recs):
    with open(path, "wb") as f:
        f.write(header)
        for r in recs:
            f.write(record_bytes(*r))


def nth(recs, rtype, n):
    """Index of the n-th record of a type (n may be negative)."""
    idx = [i for i, r in enumerate(recs) if r[0] == rtype]
    return idx[n]


def stamp(rec):
    return struct.unpack_from("<q", rec[2], 0)[0]


def set_log_stamp(rec, value):
    struct.pack_into("<q", rec[2], 0, value)


def mutate_log(src, name, edit):
    header, recs = read_log(src)
    recs = edit(recs) or recs
    out = os.path.join(WORK, name)
    write_log(out, header, recs)
    return out


# --- the matrix --------------------------------------------------------------------------------

class Case:
    def __init__(self, name, expect, make, args, message, dataset=None, ate_max=None,
                 code=0, extra=None):
        self.name, self.expect, self.make, self.args = name, expect, make, args
        self.message, self.dataset, self.ate_max, self.code = message, dataset, ate_max, code
        self.extra = extra or []  # further regular expressions stderr must match


# --- the map file: two writers, a symlinked path, implausible values (issue 45: 1, 6, 9) --------
# A map case's args is a runner (marked runs_itself): it runs its own programs and returns what
# run() returns, with the exit code replaced by a text saying what failed when the files it leaves
# are not as they must be.
MAP_HEADER, MAP_RECORD = 64, 3964
MAP_SAVE = ["--set", "map.save_interval_s=0.2"]


def map_file_state(path):
    """(True, what) for a whole map file; (False, why) for a missing, cut short or damaged one."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        return False, "cannot read: %s" % e.strerror
    if len(data) < MAP_HEADER + 4 or data[:8] != b"CSLAMMAP":
        return False, "%d bytes, not a map file" % len(data)
    count = struct.unpack_from("<I", data, 20)[0]
    if len(data) != MAP_HEADER + MAP_RECORD * count + 4:
        return False, "%d bytes for %d landmarks (cut short or appended to)" % (len(data), count)
    if zlib.crc32(data[:-4]) & 0xFFFFFFFF != struct.unpack_from("<I", data, len(data) - 4)[0]:
        return False, "CRC mismatch"
    return True, "%d landmarks, saved at %d ns" % (count, struct.unpack_from("<q", data, 28)[0])


def map_temporaries(folder, name="map.bin"):
    return [f for f in os.listdir(folder) if re.fullmatch(re.escape(name) + r"\.tmp(\.\d+)?", f)]


def two_writers_killed(dataset, rounds=KILL_ROUNDS):
    """Runner: two cleanslam started on one map, both killed with SIGKILL at a random moment,
    `rounds` times. Each round the map must be whole (the previous one or a new one); one of the
    two must be refused at start; temporaries of killed saves must not pile up."""
    def runner(folder):
        import random
        rnd = random.Random(45)
        path = os.path.join(folder, "map.bin")
        args = [prog("cleanslam"), "--dataset", dataset, "--set", "map.path=" + path] + MAP_SAVE
        texts, failed, refused, saved_before, t0 = [], [], 0, None, time.monotonic()
        for i in range(rounds):
            procs = [subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                     for _ in range(2)]
            # The one refused ends by itself; the other is killed a moment later, while it saves.
            deadline = time.monotonic() + TIMEOUT_S
            while all(p.poll() is None for p in procs) and time.monotonic() < deadline:
                time.sleep(0.01)
            time.sleep(rnd.uniform(0.0, 1.2))
            codes = []
            for p in procs:
                p.kill()
                err = p.communicate()[1].decode(errors="replace")
                codes.append(p.returncode)
                texts.append(err)
                refused += 1 if "is in use by another process" in err else 0
            ok, what = map_file_state(path)
            if not ok and (saved_before is not None or os.path.exists(path)):
                failed.append("round %d: map.bin %s" % (i + 1, what))
            saved_before = saved_before or ok
            if len(map_temporaries(folder)) > 2:
                failed.append("round %d: temporaries pile up: %s"
                              % (i + 1, map_temporaries(folder)))
            if 2 not in codes:
                failed.append("round %d: exits %s, none refused (2)" % (i + 1, codes))
        summary = ("%d rounds of two writers killed: map.bin whole after every round, %d second "
                   "writers refused, %d temporaries left" % (rounds, refused,
                                                             len(map_temporaries(folder))))
        return ("; ".join(failed) if failed else 0), "\n".join(texts + [summary]), \
            time.monotonic() - t0
    runner.runs_itself = True
    return runner


def symlinked_map(dataset, dangling):
    """Runner: map.path is a link (dangling or to a saved map) into another folder; the run must
    save through it to the target and keep the link."""
    def runner(folder):
        store = os.path.join(folder, "store")
        os.makedirs(store, exist_ok=True)
        target = os.path.join(store, "real.bin")
        link = os.path.join(folder, "map.bin")
        if os.path.lexists(link):
            os.remove(link)
        os.symlink("store/real.bin", link)
        before = None
        if not dangling:
            code, err, _ = run([prog("cleanslam"), "--dataset", dataset, "--set",
                                "map.path=" + target])
            assert code == 0, err
            # Saves replace the file by a rename, and a later save's file may reuse a freed
            # inode number: the inode and the modification time together tell a new file.
            st = os.stat(target)
            before = (st.st_ino, st.st_mtime_ns)
        code, err, secs = run([prog("cleanslam"), "--dataset", dataset, "--set",
                               "map.path=" + link] + MAP_SAVE)
        ok, what = map_file_state(target)
        problems = []
        if not os.path.islink(link):
            problems.append("map.bin is no longer a link")
        if not ok:
            problems.append("the link's target %s" % what)
        st = os.stat(target) if os.path.exists(target) else None
        if before is not None and st is not None and (st.st_ino, st.st_mtime_ns) == before:
            problems.append("the target was not replaced by a new map")
        if map_temporaries(store, "real.bin") or map_temporaries(folder):
            problems.append("temporaries left")
        return ("; ".join(problems) if problems else code), err, secs
    runner.runs_itself = True
    return runner


def saved_map(dataset):
    """A map saved by a run on `dataset`, made once."""
    out = os.path.join(WORK, "map_base", "map.bin")
    if not os.path.exists(out):
        os.makedirs(os.path.dirname(out), exist_ok=True)
        code, err, _ = run([prog("cleanslam"), "--dataset", dataset, "--set", "map.path=" + out])
        assert code == 0 and map_file_state(out)[0], err
        with open(out, "rb") as f:
            assert struct.unpack_from("<I", f.read(), 20)[0] >= 2, "the base map needs 2 landmarks"
    return out


def implausible_map(dataset, edit):
    """Runner: a saved map with one value edited and its CRC made valid again; the run must refuse
    it (moved aside whole to map.bin.refused) and save a new map."""
    def runner(folder):
        with open(saved_map(dataset), "rb") as f:
            data = bytearray(f.read())
        edit(data)
        struct.pack_into("<I", data, len(data) - 4, zlib.crc32(bytes(data[:-4])) & 0xFFFFFFFF)
        path = os.path.join(folder, "map.bin")
        for p in (path, path + ".refused"):
            if os.path.exists(p):
                os.remove(p)
        with open(path, "wb") as f:
            f.write(data)
        code, err, secs = run([prog("cleanslam"), "--dataset", dataset, "--set",
                               "map.path=" + path])
        problems = []
        try:
            with open(path + ".refused", "rb") as f:
                if f.read() != bytes(data):
                    problems.append("map.bin.refused is not the refused file")
        except OSError:
            problems.append("no map.bin.refused")
        ok, what = map_file_state(path)
        if not ok:
            problems.append("no new map: map.bin %s" % what)
        return ("; ".join(problems) if problems else code), err, secs
    runner.runs_itself = True
    return runner


REC0 = MAP_HEADER  # the first landmark's record; the second's follows


def pack(fmt, at, value):
    return lambda d: struct.pack_into(fmt, d, at, value)


def with_patch(*more):
    """The first landmark marked as having a patch (depth 1 m), then `more` edits."""
    def edit(d):
        struct.pack_into("<I", d, REC0 + 8, 1)
        struct.pack_into("<d", d, REC0 + 88, 1.0)
        for e in more:
            e(d)
    return edit


def copy_first_id(d):
    d[REC0 + MAP_RECORD:REC0 + MAP_RECORD + 8] = d[REC0:REC0 + 8]


def map_folder(name):
    def make():
        d = os.path.join(WORK, "map_" + re.sub(r"\W+", "_", name))
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        return d
    return make


def map_cases(dataset):
    """The map file's cases on `dataset` (long enough to be killed while it saves)."""
    cases = [
        Case("map: two writers, %d kill -9 rounds" % KILL_ROUNDS, "recovered",
             map_folder("two writers"),
             two_writers_killed(dataset),
             r"cleanslam: error: map: \S+/map\.bin is in use by another process \(pid \d+ "
             r"cleanslam, holding \S+/map\.bin\.lock\): two processes on one map would overwrite "
             r"each other's saves; this run does not start",
             extra=[r"%d rounds of two writers killed: map\.bin whole after every round"
                    % KILL_ROUNDS]),
        Case("map path a symlink", "recovered", map_folder("symlink"),
             symlinked_map(dataset, False),
             r"map\.bin is a symbolic link to \S+/store/real\.bin: the map is read from and saved "
             r"to \S+/store/real\.bin, and the link is kept",
             extra=[r"saved \d+ landmarks to \S+/map\.bin, a link to \S+/store/real\.bin"]),
        Case("map path a dangling symlink", "recovered", map_folder("dangling"),
             symlinked_map(dataset, True),
             r"map\.bin is a symbolic link to \S+/store/real\.bin, which does not exist yet"),
    ]
    value = "a value out of its plausible range: "
    first = r"landmark 0 \(id \d+\): "
    for name, edit, detail, at in [
        ("position 1e308", pack("<d", REC0 + 16, 1e308),
         value + first + r"position_m\[0\] = 1e\+308, allowed -10000 to 10000 m", REC0 + 16),
        ("covariance 1e308", pack("<d", REC0 + 40, 1e308),
         value + first + r"covariance xx = 1e\+308, allowed 0 to 1e\+08 m\^2", REC0 + 40),
        ("dock 1e308", pack("<d", 36, 1e308),
         value + r"header dock\.x_m = 1e\+308, allowed -10000 to 10000 m", 36),
        ("negative first depth", with_patch(pack("<d", REC0 + 88, -2.0)),
         value + first + r"first_depth_m = -2, allowed above 0, up to 10000 m", REC0 + 88),
        ("patch 3e38", with_patch(pack("<f", REC0 + 120, 3e38)),
         value + first + r"patch\[0\] = 3\.00000001e\+38, allowed 0 to 255 \(8-bit grey\)",
         REC0 + 120),
        ("saved_at INT64_MIN", pack("<q", 28, INT64_MIN),
         value + r"header saved_at_ns = -9223372036854775808, allowed 0 to 4611686018427387904",
         28),
        ("duplicate ids", copy_first_id,
         r"two landmarks with one id: landmark 1 \(id (\d+)\): id = \1, already landmark 0's",
         REC0 + MAP_RECORD),
        ("unknown flag bits", pack("<I", REC0 + 8, 0x10),
         r"flags this version does not define: " + first +
         r"flags = 0x10, allowed 0x1 \(patch\), 0x3 \(patch, anchor\) or 0", REC0 + 8),
    ]:
        cases.append(Case("map " + name, "recovered", map_folder(name),
                          implausible_map(dataset, edit),
                          r"\S+/map\.bin: refused: " + detail + r", at byte %d; moved to "
                          r"\S+/map\.bin\.refused: a new map starts" % at))
    return cases


# --- issue 45: inputs bounded, write errors told, calibrations that blind the estimator ---------

def issue45_input_cases(feat, feat60, imgs, base_log):
    """Cases of issue 45 (items 2-5, 7, 8, 11, 12): each input that never ends or is not a file is
    refused naming the file and what it is; a write that fails is told with the file and strerror
    and the exit status is 2; calibrations that leave the estimator blind are refused naming the
    key, value and range; the robot's text outputs rotate."""
    fm = prog("cleanslam")

    def fifo(name):
        path = os.path.join(WORK, name)
        if os.path.lexists(path):
            os.unlink(path)
        os.mkfifo(path)
        return path

    def folder(name):
        path = os.path.join(WORK, name)
        os.makedirs(path, exist_ok=True)
        return path

    def with_lift():
        """The features dataset with a lift.csv (a lift and a set-down)."""
        d = copy_dataset(feat, "i45_with_lift")
        with open(os.path.join(d, "encoders.csv")) as f:
            t = int(f.read().splitlines()[100].split(",")[0])
        with open(os.path.join(d, "lift.csv"), "w") as f:
            f.write("#t_ns,lifted\n%d,1\n%d,0\n" % (t, t + 10**9))
        return d

    def given(path):
        return lambda: path

    def with_file(name, file, target, source=feat):
        """A copy of a dataset whose `file` is replaced by `target()` (a FIFO, or a symbolic link
        to a device)."""
        def make():
            d = copy_dataset(source() if callable(source) else source, name)
            p = os.path.join(d, file)
            if os.path.lexists(p):
                os.unlink(p)
            t = target(p)
            if t is not None:
                os.symlink(t, p)
            return d
        return make

    def sensors(name, **values):
        """A copy of the features dataset with sensors.yaml keys set (key: value, any section)."""
        def make():
            d = copy_dataset(feat, name)
            p = os.path.join(d, "sensors.yaml")
            with open(p) as f:
                text = f.read()
            for key, value in values.items():
                text, n = re.subn(r"(\n\s*%s:) *[-0-9.e+]+" % key, r"\g<1> %s" % value, text)
                assert n == 1, key
            with open(p, "w") as f:
                f.write(text)
            return d
        return make

    def text_file(name, text):
        def make():
            p = os.path.join(WORK, name)
            with open(p, "w") as f:
                f.write(text)
            return p
        return make

    def image_case(name, edit):
        def make():
            d = copy_dataset(imgs, name)
            edit(os.path.join(d, "cam0", "data", image_files(d)[3]))
            return d
        return make

    def grey_alpha(p):
        raw = b"".join(b"\0" + b"\x80\xff" * 320 for _ in range(240))

        def chunk(kind, data):
            c = struct.pack(">I", len(data)) + kind + data
            return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
        with open(p, "wb") as f:
            header = struct.pack(">IIBBBBB", 320, 240, 8, 4, 0, 0, 0)
            f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
                    + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))

    def link_out(p):
        outside = os.path.join(WORK, "outside.png")
        shutil.copy(p, outside)
        os.unlink(p)
        os.symlink(outside, p)

    def fifo_image(p):
        os.unlink(p)
        os.mkfifo(p)

    def dataset(*extra):
        return lambda path, tum: [fm, "--dataset", path] + list(extra)

    def config(*extra):
        return lambda path, tum: [fm, "--config", path, "--dataset", feat] + list(extra)

    def log(path, tum):
        return [fm, "--log", path]

    def replay(path, tum):
        return [fm, "--replay", path]

    def sim(path, tum):
        return [prog("cleanslam-sim"), "default-room", path, "--set", "duration_s=7200"]

    rotated = os.path.join(WORK, "i45_rotated")

    def rotated_outputs():
        shutil.rmtree(rotated, ignore_errors=True)
        os.makedirs(rotated)
        return rotated

    def rotated_run(path, tum):
        return [fm, "--dataset", feat60, "--tum", os.path.join(path, "t.tum"), "--set",
                "sinks.max_file_mb=1", "--set", "sinks.max_files=2", "--set",
                "loop.publish_rate_hz=100"]

    def rotated_bounded():
        """The TUM file and its .cov rotated together: 2 files of each, each within 1 MB and a
        line."""
        names = sorted(os.listdir(rotated))
        problems = []
        for stem in ("t.tum", "t.tum.cov"):
            if stem + ".1" not in names:
                problems.append("no %s.1" % stem)
        for n in names:
            if n.endswith(".2") or os.path.getsize(os.path.join(rotated, n)) > 2**20 + 1000:
                problems.append("%s: beyond the rotation" % n)
        return problems

    def full_tum():
        """A TUM path and its .cov that lead to /dev/full (nothing is created in /dev)."""
        tum = os.path.join(WORK, "i45_full.tum")
        for p in (tum, tum + ".cov"):
            if os.path.lexists(p):
                os.unlink(p)
            os.symlink("/dev/full", p)
        return tum

    big = "# a comment line of a configuration that goes on and on\n" * 40000
    not_file = r"is a %s, not a regular file"
    cases = [
        # 2: write errors told, exit status 2
        Case("i45 --record and --tum on /dev/full", "refused", given(feat),
             lambda path, tum: [fm, "--dataset", path, "--record", "/dev/full", "--tum",
                                full_tum()],
             r"^(?![\s\S]*buffer was full)[\s\S]*/dev/full: cannot write: No space left on device; "
             r"\d+ failed write\(s\), \d+ record\(s\) dropped", code=2,
             extra=[r"i45_full\.tum: cannot write: No space left on device: the trajectory is "
                    r"incomplete", r"i45_full\.tum\.cov: cannot write: No space left"]),
        Case("i45 diagnostics on /dev/full", "refused", given(feat),
             dataset("--set", "sinks.diagnostics=/dev/full"),
             r"/dev/full: cannot write: No space left on device: the diagnostics are incomplete",
             code=2),
        # 3, 5: a directory where a file is expected
        Case("i45 --log DIR", "refused", lambda: folder("i45_dir"), log,
             r"i45_dir: " + not_file % "directory", code=2),
        Case("i45 --replay DIR", "refused", lambda: folder("i45_dir"), replay,
             r"i45_dir: " + not_file % "directory", code=2),
        Case("i45 --config DIR", "refused", lambda: folder("i45_dir"), config(),
             r"i45_dir: " + not_file % "directory", code=2),
        # 4: inputs that never end
        Case("i45 --config /dev/zero", "refused", given("/dev/zero"), config(),
             r"/dev/zero: " + not_file % "character device", code=2),
        Case("i45 --log /dev/zero", "refused", given("/dev/zero"), log,
             r"/dev/zero: " + not_file % "character device", code=2),
        Case("i45 gyro.csv linked to /dev/zero", "refused",
             with_file("i45_gyro_zero", "gyro.csv", lambda p: "/dev/zero"), dataset(),
             r"gyro\.csv: " + not_file % "character device", code=2),
        Case("i45 sensors.yaml linked to /dev/zero", "refused",
             with_file("i45_sensors_zero", "sensors.yaml", lambda p: "/dev/zero"), dataset(),
             r"sensors\.yaml: " + not_file % "character device", code=2),
        Case("i45 --config FIFO", "refused", lambda: fifo("i45_config.fifo"), config(),
             r"i45_config\.fifo: " + not_file % "FIFO", code=2),
        Case("i45 --log FIFO", "refused", lambda: fifo("i45_log.fifo"), log,
             r"i45_log\.fifo: " + not_file % "FIFO", code=2),
        Case("i45 --replay FIFO", "refused", lambda: fifo("i45_replay.fifo"), replay,
             r"i45_replay\.fifo: " + not_file % "FIFO", code=2),
        Case("i45 sensors.yaml FIFO", "refused",
             with_file("i45_sensors_fifo", "sensors.yaml", lambda p: os.mkfifo(p)), dataset(),
             r"sensors\.yaml: " + not_file % "FIFO", code=2),
        Case("i45 lift.csv FIFO", "refused",
             with_file("i45_lift_fifo", "lift.csv", lambda p: os.mkfifo(p), source=with_lift),
             dataset(), r"lift\.csv: " + not_file % "FIFO", code=2),
        Case("i45 configuration of 2 MB", "refused", text_file("i45_big.yaml", big), config(),
             r"i45_big\.yaml: \d+ bytes, more than the 1048576 bytes readers::kYamlFileLimit "
             r"allows", code=2),
        # 7: calibrations that leave the estimator blind
        Case("i45 ticks_per_meter 1e-300", "refused",
             sensors("i45_ticks", ticks_per_meter_left="1e-300"), dataset(),
             r"wheels\.ticks_per_meter_left: 1e-300 is out of range \[100, 1e\+07\]", code=2),
        Case("i45 fx 1e-6", "refused", sensors("i45_fx", fx="1e-6"), dataset(),
             r"camera\.fx: 1e-06 is out of range \[42\.87, 1829\]: the field of view across "
             r"camera\.width 320 px must be 10 to 150 degrees", code=2),
        Case("i45 cx 1e4 with fx 1e5", "refused", sensors("i45_cx", cx="1e4", fx="1e5"),
             dataset(), r"camera\.cx: 10000 is out of range \[-0\.5, 319\.5\]: the principal "
             r"point must be inside the image", code=2,
             extra=[r"camera\.fx: 100000 is out of range"]),
        Case("i45 camera 16384x16384", "refused",
             sensors("i45_16384", width="16384", height="16384"), dataset(),
             r"camera\.width: 16384 is out of range \[1, 320\]: the front end takes images "
             r"of at most 320x240", code=2),
        # 8: smaller silent acceptances
        Case("i45 two YAML documents", "refused",
             text_file("i45_two_docs.yaml", "loop:\n  frame_rate_hz: 2\n---\nsinks:\n  tum: x\n"),
             config(), r"i45_two_docs\.yaml:3: a second YAML document", code=2),
        Case("i45 map.save_interval_s 1e-9", "refused", given(feat),
             dataset("--set", "map.save_interval_s=1e-9"),
             r"map\.save_interval_s: 1e-09 is out of range \[0\.1, 86400\]: a save holds the loop",
             code=2),
        Case("i45 image linked out of the dataset", "refused", image_case("i45_img_out", link_out),
             dataset(), r"outside the dataset folder \S+i45_img_out \(a symbolic link out of it\)",
             code=2),
        Case("i45 grey+alpha PNG", "refused", image_case("i45_img_alpha", grey_alpha), dataset(),
             r"\.png: PNG has an alpha channel", code=2),
        Case("i45 FIFO image", "refused", image_case("i45_img_fifo", fifo_image), dataset(),
             r"\.png: " + not_file % "FIFO", code=2),
        # 11: a duration the path cannot fill
        Case("i45 sim duration beyond the path", "refused",
             lambda: os.path.join(WORK, "i45_sim_7200"), sim,
             r"duration_s 7200 s is longer than the path, which ends at 470\.\d s: set duration_s "
             r"to at most 470\.\d, or path\.repeats to 16", code=1),
        # 12: the robot's text outputs rotate
        Case("i45 outputs rotate", "recovered", rotated_outputs, rotated_run,
             r"t\.tum rotated \d+ time\(s\) at 1 MB \(sinks\.max_file_mb\)"),
    ]
    cases[-1].post = rotated_bounded
    return cases


def main():
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    feat = os.path.join(WORK, "features")
    imgs = os.path.join(WORK, "images")
    simulate(feat, 20)
    feat60 = os.path.join(WORK, "features60")  # turns enough to measure the camera time offset
    simulate(feat60, 60)
    simulate(imgs, 8, "camera.mode=images")
    base_tum = os.path.join(WORK, "base.tum")
    base_log = os.path.join(WORK, "base.log")
    code, err, _ = run([prog("cleanslam"), "--dataset", feat, "--tum", base_tum, "--record",
                        base_log])
    assert code == 0, err
    base = ate(feat, base_tum)
    img_tum = os.path.join(WORK, "images.tum")
    code, err, _ = run([prog("cleanslam"), "--dataset", imgs, "--tum", img_tum])
    assert code == 0, err
    base_img = ate(imgs, img_tum)
    bound = 2.0 * base + 0.01
    bound_img = 2.0 * base_img + 0.01
    print("baselines: features ATE %.4f m (bound %.4f), images ATE %.4f m (bound %.4f)"
          % (base, bound, base_img, bound_img))

    def ds_case(name, file, edit, source=feat):
        def make():
            d = copy_dataset(source, name)
            if file is None:
                edit(d)
            else:
                edit_csv(d, file, edit)
            return d
        return make

    def log_case(name, edit, src=None):
        return lambda: mutate_log(src or base_log, name + ".log", edit)

    def gyro_rows_shifted(rows):
        for r in rows[len(rows) // 2:]:
            r[0] = str(int(r[0]) + YEAR_NS)
        return rows

    def wrap_ticks(rows):
        for r in rows:
            for i in (1, 2):
                r[i] = str((int(r[i]) + 2**32 - 5000) % 2**32)
        return rows

    def time_offset(value):
        def edit(d):
            p = os.path.join(d, "sensors.yaml")
            with open(p) as f:
                text = f.read()
            text, n = re.subn(r"time_offset_s: *[-0-9.e]+", "time_offset_s: %s" % value, text)
            assert n == 1, "no camera.time_offset_s in sensors.yaml"
            with open(p, "w") as f:
                f.write(text)
        return edit

    def corrupt_image(d):
        p = os.path.join(d, "cam0", "data", image_files(d)[5])
        with open(p, "r+b") as f:
            f.seek(60)
            f.write(b"\xff" * 200)

    def black_images(d):
        for name in image_files(d)[4:8]:
            with open(os.path.join(d, "cam0", "data", name), "wb") as f:
                f.write(png_gray(320, 240, b"\0" * (320 * 240)))

    def truncate_csv(d):
        p = os.path.join(d, "encoders.csv")
        with open(p, "rb") as f:
            data = f.read()
        with open(p, "wb") as f:
            f.write(data[:-7])

    def log_stamp(rtype, n, value):
        def edit(recs):
            set_log_stamp(recs[nth(recs, rtype, n)], value)
        return edit

    def log_early_encoder(recs):
        r = recs[nth(recs, T_ENCODER, 100)]
        set_log_stamp(r, stamp(r) + 900_000_000)

    def log_bad_payload(recs):
        i = nth(recs, T_GYRO, 300)
        recs[i][2] = recs[i][2][:10]

    def log_config_altered(recs):
        i = nth(recs, T_CONFIG, 0)
        text = recs[i][2][8:].decode()
        text2 = re.sub(r"publish_rate_hz: *[0-9.]+", "publish_rate_hz: 10", text)
        assert text2 != text
        recs[i][2] = recs[i][2][:8] + text2.encode()

    def log_tiny_frame(recs):
        i = nth(recs, T_FRAME, 10)
        t = stamp(recs[i]) + 100_000_000
        payload = struct.pack("<qIHHHH", t, 999, 3, 3, 0, 0) + b"\x80" * 9
        recs.insert(i + 1, [T_FRAME, 0, bytearray(payload)])

    def log_nan(recs):
        struct.pack_into("<d", recs[nth(recs, T_GYRO, 500)][2], 8, float("nan"))

    def log_duplicate(recs):
        i = nth(recs, T_GYRO, 400)
        recs.insert(i + 1, [recs[i][0], recs[i][1], bytearray(recs[i][2])])

    def log_swap(recs):
        a, b = nth(recs, T_ENCODER, 150), nth(recs, T_ENCODER, 151)
        recs[a], recs[b] = recs[b], recs[a]

    def log_bit_flip(name):
        def make():
            out = os.path.join(WORK, name + ".log")
            with open(base_log, "rb") as f:
                data = bytearray(f.read())
            data[len(data) // 2] ^= 0x10
            with open(out, "wb") as f:
                f.write(data)
            return out
        return make

    def log_truncated(name):
        def make():
            out = os.path.join(WORK, name + ".log")
            with open(base_log, "rb") as f:
                data = f.read()
            with open(out, "wb") as f:
                f.write(data[:len(data) * 2 // 3 + 5])
            return out
        return make

    rotated = os.path.join(WORK, "rotated", "run.log")

    def record_rotated():
        os.makedirs(os.path.dirname(rotated), exist_ok=True)
        code, err, _ = run([prog("cleanslam"), "--dataset", imgs, "--record", rotated,
                            "--set", "recorder.max_file_mb=1", "--set", "recorder.max_files=4"])
        assert code == 0 and os.path.exists(rotated + ".1"), err
        return rotated

    def lone_newest():
        record_rotated()
        out = os.path.join(WORK, "lone", "run.log")
        os.makedirs(os.path.dirname(out), exist_ok=True)
        shutil.copy(rotated, out)
        return out

    def joined():
        record_rotated()
        out = os.path.join(WORK, "rotated", "joined.log")
        with open(out, "wb") as f:
            for p in [rotated + ".1", rotated]:
                with open(p, "rb") as g:
                    f.write(g.read())
        return out

    def dataset_run(make, *extra):
        return lambda path: [prog("cleanslam"), "--dataset", path] + list(extra)

    cases = [
        # time stamps
        Case("gyro.csv last stamp INT64_MAX", "recovered", ds_case("ds_int64max", "gyro.csv",
             set_stamp(-1, INT64_MAX)), "dataset",
             r"gyro\.csv:\d+: t_ns: time stamp 9223372036854775807 is more than 86400\.0 s "
             r"\(loop\.max_span_s\).*row refused", feat, bound),
        Case("gyro.csv stamp 9e18 mid-file", "recovered", ds_case("ds_9e18", "gyro.csv",
             set_stamp(1000, 9 * 10**18)), "dataset",
             r"gyro\.csv:1002: t_ns: time stamp 9000000000000000000 is more than", feat, bound),
        Case("encoders.csv stamp INT64_MIN", "refused", ds_case("ds_int64min", "encoders.csv",
             set_stamp(50, INT64_MIN)), "dataset",
             r"encoders\.csv:52: t_ns: negative time stamp", code=2),
        Case("gyro.csv second half a year late", "recovered", ds_case("ds_year", "gyro.csv",
             gyro_rows_shifted), "dataset",
             r"gyro\.csv:\d+: t_ns: time stamp \d+ is more than 86400", feat, 0.5,
             extra=[r"gyro silent", r"rejected time_jump: 1000"]),
        Case("log gyro stamp 9e18", "recovered", log_case("log_9e18",
             log_stamp(T_GYRO, 700, 9 * 10**18)), "log",
             r"offset \d+: gyro record: time stamp 9000000000000000000 is more than 86400 s",
             feat, bound),
        Case("log gyro stamp a year late", "recovered", log_case("log_year",
             lambda r: set_log_stamp(r[nth(r, T_GYRO, 700)],
                                     stamp(r[nth(r, T_GYRO, 700)]) + YEAR_NS)),
             "log", r"offset \d+: gyro record: time stamp \d+ is more than 86400 s", feat, bound),
        Case("log gyro stamp INT64_MIN", "recovered", log_case("log_int64min",
             log_stamp(T_GYRO, 700, INT64_MIN)), "log",
             r"offset \d+: gyro record: time stamp -9223372036854775808 is negative: refused",
             feat, bound),
        Case("replayed clock record INT64_MAX", "told", log_case("log_clock_max",
             log_stamp(T_CLOCK, 1000, INT64_MAX)), "replay",
             r"offset \d+: clock record: time stamp 9223372036854775807 is more than", code=1),
        Case("log encoder stamped 0.9 s early", "recovered", log_case("log_early",
             log_early_encoder), "log",
             r"offset \d+: encoder record: time stamp \d+ is after that of the next encoder",
             feat, bound, extra=[r"rejected out_of_order: 1\b"]),
        # losses told
        Case("log payload that does not decode", "recovered", log_case("log_payload",
             log_bad_payload), "log",
             r"offset \d+: gyro record: 10 payload bytes with a valid checksum that do not decode",
             feat, bound),
        Case("log configuration altered", "refused", log_case("log_config", log_config_altered),
             "replay", r"configuration record's hash \(0x[0-9a-f]+\) is not that of its text",
             code=2),
        Case("rotated log, later file alone", "refused", record_rotated, "replay",
             r"run\.log is file 1 of a rotated recording[\s\S]*cat \S*run\.log\.1 \S*run\.log "
             r"> joined\.log", code=2),
        Case("rotated log, first file deleted", "refused", lambda: lone_newest(), "replay",
             r"lone/run\.log\.1, which the run's start needs, does not exist", code=2),
        Case("rotated log, files joined", "recovered", joined, "replay",
             r"output records reproduced bit for bit"),
        Case("3x3 frame in a log", "recovered", log_case("log_tiny", log_tiny_frame), "log",
             r"input refused \(image_size\)", feat, bound, extra=[r"rejected image_size: 1\b"]),
        Case("corrupt PNG", "recovered", ds_case("ds_png", None, corrupt_image, imgs), "dataset",
             r"cam0/data\.csv:7: filename: \S+\.png: .*went on without its image", imgs,
             bound_img),
        Case("camera time offset +0.8 s", "recovered",
             ds_case("ds_offset", None, time_offset(0.8), feat60), "dataset",
             r"sensors\.yaml:\d+: camera\.time_offset_s: 0\.8 s is more than 0\.5 s", feat60, 1.0,
             extra=[r"camera time offset: the data suggest [+-]0\.0\d+ s",
                    r"camera\.time_offset_s looks off by -0\.[78]\d* s"]),
        Case("camera time offset +2 s", "refused", ds_case("ds_offset2", None, time_offset(2.0)),
             "dataset", r"camera\.time_offset_s: 2 is out of range \[-1, 1\]", code=2),
        # already handled
        Case("encoders.csv cut short", "recovered", ds_case("ds_trunc", None, truncate_csv),
             "dataset", r"encoders\.csv:401: the last line has no line end: the file was cut "
             r"short; its last row is skipped", feat, bound),
        Case("encoders.csv duplicate row", "refused", ds_case("ds_dup", "encoders.csv",
             lambda rows: rows[:100] + [rows[99]] + rows[100:]), "dataset",
             r"encoders\.csv:102: t_ns: time stamp \d+ is not after the previous row's", code=2),
        Case("gyro.csv swapped rows", "refused", ds_case("ds_swap", "gyro.csv",
             lambda rows: rows[:300] + [rows[301], rows[300]] + rows[302:]), "dataset",
             r"gyro\.csv:303: t_ns: time stamp \d+ is not after", code=2),
        Case("gyro.csv NaN", "refused", ds_case("ds_nan", "gyro.csv",
             lambda rows: rows[:300] + [[rows[300][0], "nan"]] + rows[301:]), "dataset",
             r"gyro\.csv:302: wz_rad_s: expected a finite number", code=2),
        Case("encoder ticks wrap around", "recovered", ds_case("ds_wrap", "encoders.csv",
             wrap_ticks), "dataset", None, feat, bound),
        Case("black frames", "recovered", ds_case("ds_black", None, black_images, imgs), "dataset",
             None, imgs, bound_img),
        Case("log truncated", "recovered", log_truncated("log_trunc"), "replay",
             r"truncated at byte \d+.*\n(.*\n)*.*reproduced bit for bit \(up to the truncation\)"),
        Case("log bit flip", "recovered", log_bit_flip("log_flip"), "log",
             r"1 (bad_crc|bad_sync|bad_length) record\(s\) skipped", feat, bound),
        Case("log duplicate record", "recovered", log_case("log_dup", log_duplicate), "log",
             r"input refused \(out_of_order\)", feat, bound),
        Case("log swapped encoder records", "recovered", log_case("log_swap", log_swap), "log",
             r"encoder record: time stamp \d+ is after that of the next encoder", feat, bound,
             extra=[r"rejected out_of_order: 1\b"]),
        Case("log NaN gyro", "recovered", log_case("log_nan", log_nan), "log",
             r"input refused \(non_finite\)", feat, bound),
    ]
    cases += map_cases(feat60)
    cases += issue45_input_cases(feat, feat60, imgs, base_log)

    rows, failures = [], 0
    for c in cases:
        if ONLY and not any(o in c.name for o in ONLY):
            continue
        path = c.make()
        tum = os.path.join(WORK, re.sub(r"\W+", "_", c.name) + ".tum")
        if getattr(c.args, "runs_itself", False):
            args = None  # a runner: it runs its programs itself
        elif c.args == "dataset":
            args = [prog("cleanslam"), "--dataset", path, "--tum", tum]
        elif c.args == "log":
            args = [prog("cleanslam"), "--log", path, "--tum", tum]
        elif callable(c.args):
            args = c.args(path, tum)
        else:
            args = [prog("cleanslam"), "--replay", path, "--replay-out", path + ".replay"]
        code, err, secs = run(args) if args is not None else c.args(path)
        problems = []
        if code != c.code:
            problems.append("exit %s, expected %s" % (code, c.code))
        shown = ""
        if c.message is not None:
            m = re.search(c.message, err)
            if m is None:
                problems.append("no message /%s/" % c.message)
            else:
                shown = m.group(0).splitlines()[0]
        for e in c.extra:
            if re.search(e, err) is None:
                problems.append("no /%s/" % e.strip())
        problems += c.post() if getattr(c, "post", None) else []
        value = None
        if c.ate_max is not None and code == 0:
            value = ate(c.dataset, tum)
            if value is None or value > c.ate_max:
                problems.append("ATE %s m above %.4f m" % (value, c.ate_max))
        failures += 1 if problems else 0
        rows.append((c.name, c.expect, "FAIL: " + "; ".join(problems) if problems else "ok",
                     "%.4f" % value if value is not None else "-", "%.1f" % secs, shown))
        if problems:
            sys.stderr.write("--- %s: stderr ---\n%s\n" % (c.name, err[-3000:]))

    print("\n%-36s %-9s %-6s %-8s %-5s %s" % ("fault", "expected", "result", "ATE m", "s",
                                              "message"))
    for r in rows:
        print("%-36s %-9s %-6s %-8s %-5s %s" % (r[0], r[1], r[2] if r[2] == "ok" else "FAIL",
                                                r[3], r[4], r[5][:150]))
        if r[2] != "ok":
            print("    " + r[2])
    print("\n%d of %d cases as expected" % (len(rows) - failures, len(rows)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
