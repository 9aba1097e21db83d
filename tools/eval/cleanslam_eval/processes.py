"""Child processes that a stop (SIGINT or SIGTERM) ends with the script that started them."""
import signal
import subprocess
import threading

_lock = threading.Lock()
_running = set()
_stopping = threading.Event()


class Stopped(Exception):
    """A stop signal arrived; args[0] names it."""


def run(cmd):
    """subprocess.run(cmd) with stdout and stderr captured as text; Stopped once a stop began."""
    with _lock:
        if _stopping.is_set():
            raise Stopped("stopping")
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        _running.add(p)
    try:
        out, err = p.communicate()
    finally:
        with _lock:
            _running.discard(p)
    return subprocess.CompletedProcess(cmd, p.returncode, out, err)


def end_children():
    """Starts no more children and terminates the running ones."""
    with _lock:
        _stopping.set()
        procs = list(_running)
    for p in procs:
        p.terminate()


def raise_on_sigterm():
    """SIGTERM raises Stopped("SIGTERM") in the main thread, as SIGINT raises KeyboardInterrupt."""
    def handler(signum, _frame):
        raise Stopped(signal.Signals(signum).name)
    signal.signal(signal.SIGTERM, handler)
