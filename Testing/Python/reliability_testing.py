"""Fault injection for the tests of the batch jobs (test_reliability_main.py,
test_reliability_snapshot.py): small tmpfs mounts (root only; the tests skip those cases with
a message elsewhere), a folder's content by hash, running a job and signalling it when its
output shows a given line, and the checks every outcome must pass (exit code, listed files
present and valid, the previous output intact).
"""
import hashlib
import json
import os
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "Examples"))
import batch_output as B  # noqa: E402


class Tmpfs(object):
    """A tmpfs of `kib` KiB mounted at `folder` (mount -t tmpfs: root only). ok is False, with
    reason, where it cannot be mounted."""

    def __init__(self, folder, kib):
        self.folder = folder
        os.makedirs(folder, exist_ok=True)
        run = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%dk" % kib, "tmpfs", folder],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             universal_newlines=True)
        self.ok = run.returncode == 0
        self.reason = run.stdout.strip() or "mount exit code %d" % run.returncode

    def remount(self, options):
        return subprocess.run(["mount", "-o", "remount," + options, self.folder]).returncode == 0

    def fill(self, leave_bytes):
        """Fills the file system up to `leave_bytes` free (a filler file); returns what is
        free then."""
        filler = os.path.join(self.folder, "filler")
        if os.path.exists(filler):
            os.remove(filler)
        free = B.free_bytes(self.folder)
        size = max(0, free - leave_bytes)
        with open(filler, "wb") as f:
            chunk = b"\0" * (1 << 20)
            while size > 0:
                try:
                    f.write(chunk[:size])
                except OSError:
                    break
                size -= min(size, len(chunk))
        return B.free_bytes(self.folder)

    def unfill(self):
        filler = os.path.join(self.folder, "filler")
        if os.path.exists(filler):
            os.remove(filler)

    def close(self):
        subprocess.run(["umount", "-l", self.folder])


def unmount_under(folder):
    """Unmounts the tmpfs mounts a killed earlier run left under `folder`."""
    if os.path.isdir(folder):
        for root, dirs, _ in os.walk(folder):
            for d in dirs:
                if os.path.ismount(os.path.join(root, d)):
                    subprocess.run(["umount", "-l", os.path.join(root, d)])


def can_mount(scratch):
    """(True, "") when a tmpfs can be mounted here, else (False, why)."""
    probe = Tmpfs(os.path.join(scratch, "mount-probe"), 64)
    if probe.ok:
        probe.close()
    return probe.ok, probe.reason


def mounted_tmpfs(scratch, kib, what):
    """A Tmpfs of `kib` KiB at scratch/tmpfs; None, with `what` reported skipped, where no
    tmpfs can be mounted here (not root)."""
    ok, why = can_mount(scratch)
    if not ok:
        print("SKIP: %s: cannot mount a tmpfs here (%s)" % (what, why))
        return None
    return Tmpfs(os.path.join(scratch, "tmpfs"), kib)


def last_line(output):
    """The last line of a job's output, where it says why it stopped ("" when silent)."""
    return output.strip().splitlines()[-1] if output.strip() else ""


def content(folder):
    """{relative path: sha1} of every file under `folder` (hidden ones too)."""
    out = {}
    for root, _, files in os.walk(folder):
        for name in files:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                out[os.path.relpath(path, folder)] = hashlib.sha1(f.read()).hexdigest()
    return out


# A pvbatch that could not open its window (an X server lost or refused under load: VTK
# aborts) says one of these; such a run is no result of the job and is started again.
X_FAILURES = ("bad X server connection", "Cannot create GLX context", "Xvfb failed to start",
              "Can't open display", "cannot open display", "CreateAWindow")


def x_failure(output):
    return any(words in output for words in X_FAILURES)


def _pvbatch_in_group(pgid):
    """The pid of the pvbatch process of process group `pgid` (under xvfb-run), or None."""
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % entry) as f:
                stat = f.read()
        except OSError:
            continue
        comm = stat[stat.index("(") + 1:stat.rindex(")")]
        fields = stat[stat.rindex(")") + 2:].split()
        if comm.startswith("pvbatch") and int(fields[2]) == pgid:  # pvbatch3.11 on Debian
            return int(entry)
    return None


class Job(object):
    """A pvbatch job started under its own X server (xvfb-run -a, its own process group),
    its output collected line by line; signal_at(text, signum) sends `signum` to the pvbatch
    process when a line starting with `text` appears (or after `delay` seconds when `text`
    is None); wait() returns (exit code, output). Exit codes are the shell's: 128 + N for a
    process ended by signal N (SIGKILL: 137). `memory_limit`: pvbatch's address-space limit
    in bytes (ulimit -v), not the X server's."""

    def __init__(self, command, memory_limit=None, env=None):
        if memory_limit:  # pvbatch's own limit, not the X server's
            command = ["sh", "-c", 'ulimit -v %d && exec "$@"' % (memory_limit // 1024),
                       "sh"] + list(command)
        display = 100 + int.from_bytes(os.urandom(2), "little") % 800
        command = ["xvfb-run", "-a", "-n", str(display), "-s", "-screen 0 1280x1024x24 -noreset"] + \
            list(command)
        self.proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     universal_newlines=True, start_new_session=True,
                                     env=env)
        self.lines = []
        self.triggers = []
        self.sent = None
        self._reader = threading.Thread(target=self._read)
        self._reader.start()

    def _read(self):
        for line in self.proc.stdout:
            self.lines.append(line)
            for text, signum in list(self.triggers):
                if line.startswith(text) and self.sent is None:
                    self._send(signum)

    def _send(self, signum):
        """To the job's pvbatch (not xvfb-run, not the snapshot tool's workers)."""
        for _ in range(100):
            pid = _pvbatch_in_group(self.proc.pid)
            if pid is not None or self.proc.poll() is not None:
                break
            time.sleep(0.1)
        if pid is None:
            return
        self.sent = signum
        try:
            os.kill(pid, signum)
        except OSError:
            pass

    def signal_at(self, text, signum, delay=0.0):
        if text is None:
            threading.Timer(delay, self._send, (signum,)).start()
        else:
            self.triggers.append((text, signum))

    def wait(self, timeout=300):
        try:
            self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, 9)
            self.proc.wait()
        self._reader.join()
        return self.proc.returncode, "".join(self.lines)


def run(command, at=None, signum=None, delay=0.0, attempts=3, **kw):
    """Runs a Job (signalled at the line `at`, or after `delay` s when `at` is None and
    `signum` is given); a run whose pvbatch could not open its window is started again, up
    to `attempts` times. Returns (exit code, output, the signal sent or None)."""
    for attempt in range(attempts):
        job = Job(command, **kw)
        if signum is not None:
            job.signal_at(at, signum, delay)
        code, output = job.wait()
        if code == 0 or not x_failure(output) or attempt == attempts - 1:
            return code, output, job.sent
        print("(pvbatch could not open its window: started again)")


def main_job_outputs_valid(folder, checker, label):
    """The main job's output folder is complete and true: report.json parses, every picture
    it lists exists and decodes; every picture of the job is listed. True when so."""
    report_path = os.path.join(folder, "report.json")
    if not checker.check(B.check_json(report_path) is None,
                         "%s: report.json parses" % label):
        return False
    with open(report_path) as f:
        report = json.load(f)
    images = report.get("images", {})
    bad = {k: B.check_png(p) for k, p in images.items() if B.check_png(p)}
    pngs = sorted(n[:-4] for n in os.listdir(folder) if n.endswith(".png"))
    ok = checker.check(images and not bad and sorted(images) == pngs and all(
        os.path.dirname(p) == os.path.abspath(folder) for p in images.values()),
        "%s: the %d pictures report.json lists exist in the folder and decode%s"
        % (label, len(images), " (bad: %s)" % bad if bad else ""))
    leftovers = [n for n in os.listdir(folder) if ".part" in n]
    return checker.check(not leftovers, "%s: no temporary files (%s)" % (label, leftovers)) \
        and ok


def ran_or_refused(folder, checker, label, code, message, refusal, why, previous):
    """A main job run under a limit either succeeded, with valid outputs in `folder`, or
    exited 1 with `message` (its last line) saying `why` (`refusal`: it does) and left the
    previous output `previous` (content()) as it was. Returns the output now there."""
    print("%s: exit %d, %s" % (label, code, message))
    if code == 0:
        main_job_outputs_valid(folder, checker, label)
        return content(folder)
    checker.check(code == 1 and refusal, "%s: exit code 1 and %s: %s" % (label, why, message))
    checker.check(content(folder) == previous, "%s: the previous output as it was" % label)
    return previous


def no_staging_left(parent, base, checker, label):
    left = [n for n in os.listdir(parent) if n.startswith("." + base + ".run-")]
    return checker.check(not left, "%s: no staging folder left (%s)" % (label, left))
