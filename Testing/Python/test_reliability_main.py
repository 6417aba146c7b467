"""The main job (Examples/transfer_function.py) under faults, on the real 3-channel brain at
half resolution (--upsample 0.5, 6D features, PCA, no methods.png: a few seconds a run).

After a complete run into OUT, each fault hits a second run into the same OUT:
  - SIGINT and SIGTERM when the job reports its read, reduction, widget and best-viewpoint
    stages: exit code 130 / 143, OUT as it was (every file by hash), no staging folder and
    no temporary file left;
  - SIGKILL at the same moments: OUT as it was; the next run removes the staging folder;
  - a small tmpfs (root mounts one; skipped with a message where it cannot) filled to
    several levels, from 16 KiB free to a little more than the outputs need: exit code 1
    with a message naming "disk full" (and the file, past the check before the chain) or
    exit code 0 with everything complete; the previous complete output on the tmpfs
    intact after each failure;
  - the tmpfs remounted read-only: exit code 1, "read-only file system", before anything
    is read;
  - a second job on the same output folder while the first holds its lock: exit code 1,
    "in use by another run";
  - memory: the job's estimate refusing it before anything is read (MCV_MEMORY_LIMIT_MB=1),
    a filter's own check stopping it (--no-memory-check, MCV_MEMORY_LIMIT_MB=8: the readers
    fit, DimensionReduction "needs 41.1 MiB ... but only 8.0 MiB is available"), and ulimit -v
    at 0.5, 1, 1.5, 2 and 4 GB: exit code 1 with the message (127 with the loader's message
    where pvbatch cannot even start), or 0 with everything complete; never a crash; OUT as
    it was after each failure.
After each: no file report.json lists is missing or invalid.
"""
import os
import shutil
import signal
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mcv_testing as T  # noqa: E402
import reliability_testing as R  # noqa: E402

C = T.Checker("test_reliability_main")
for name in ("ch2.nii.gz", "aal.nii.gz", "brodmann.nii.gz"):
    T.data_file(name)
work = os.path.join(T.output_dir(), "reliability_main")
R.unmount_under(work)  # a killed earlier run's tmpfs
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
PVBATCH = os.path.realpath("/proc/self/exe")


def job_command(output):
    command = [PVBATCH, os.path.join(T.REPO, "Examples", "transfer_function.py"),
               "--features", "6D", "--method", "PCA", "--no-methods", "--upsample", "0.5",
               "--reference-size", "1000", "--widgets", "3", "--size", "240", "180",
               "--output", output]
    if os.environ.get("MCV_PLUGIN"):
        command += ["--plugin", os.environ["MCV_PLUGIN"]]
    return command


def run_job(output, extra=(), **kw):
    """(exit code, output, signal sent) of the job on `output` (R.run: its own X server)."""
    return R.run(job_command(output) + list(extra), **kw)


def complete_run(output, label):
    code, text, _ = run_job(output)
    print(text[-1500:])
    C.check(code == 0, "%s: exit code 0 (%d)" % (label, code))
    R.main_job_outputs_valid(output, C, label)
    R.no_staging_left(os.path.dirname(output), os.path.basename(output), C, label)
    return R.content(output)


out = os.path.join(work, "out")
before = complete_run(out, "first run")
C.check(set(before) == {"best.png", "worst.png", "dual_domain.png", "domain.png",
                        "spectrum.png", "report.json", "model.mcvmodel",
                        "transfer_function.mcvtf"},
        "first run: the eight outputs and nothing else %s" % sorted(before))

# Signals at several moments of a second run into the same folder.
moments = [("read ", signal.SIGINT), ("reduction ", signal.SIGTERM),
           ("seed widgets", signal.SIGINT), ("best viewpoint", signal.SIGTERM),
           (None, signal.SIGINT)]
for text, signum in moments:
    label = "%s at %s" % (signal.Signals(signum).name, text.strip() if text else "start")
    code, output, sent = run_job(out, at=text, signum=signum, delay=3.0)
    C.check(sent == signum and code == 128 + signum,
            "%s: exit code %d (expected %d; signal sent: %s)" % (label, code, 128 + signum, sent))
    C.check(R.content(out) == before, "%s: the previous output as it was" % label)
    R.no_staging_left(work, "out", C, label)
    # At the start the signal may come before Python runs the script (pvbatch's own
    # handlers end it then, before anything is written): the message only after a stage.
    if text is not None:
        C.check("stopped: interrupted by %s" % signal.Signals(signum).name in output,
                "%s: says it was interrupted" % label)

for text in ("read ", "seed widgets", "best viewpoint"):
    label = "SIGKILL at %s" % text.strip()
    code, output, _ = run_job(out, at=text, signum=signal.SIGKILL)
    C.check(code == 128 + signal.SIGKILL, "%s: killed (%d)" % (label, code))
    C.check(R.content(out) == before, "%s: the previous output as it was" % label)
complete_run(out, "run after the kills")  # removes the killed runs' staging folders

# A second job while the first holds the lock.
first = R.Job(job_command(out))
first.signal_at("read ", signal.SIGSTOP)
while first.sent is None and first.proc.poll() is None:
    time.sleep(0.2)
code, output, _ = run_job(out)
C.check(code == 1 and "in use by another run" in output,
        "a second job on the same folder stops: %d %s" % (code, output.strip()[-200:]))
first._send(signal.SIGCONT)
code, text = first.wait()
C.check(code == 0 or R.x_failure(text), "the first job then finishes (%d)" % code)
before = R.content(out)

# The job's memory estimate refuses it before anything is read; without the estimate
# (--no-memory-check), the filter's own check stops it with the filter's message.
env = dict(os.environ, MCV_MEMORY_LIMIT_MB="1")
code, output, _ = run_job(out, env=env)
last = R.last_line(output)
C.check(code == 1 and last.startswith("error: the job needs") and "available" in last and
        "\nread " not in "\n" + output,
        "the job's estimate refuses it before reading: %d %s" % (code, last))
env["MCV_MEMORY_LIMIT_MB"] = "8"  # the readers fit (6.8 MiB each), the reduction not
code, output, _ = run_job(out, env=env, extra=["--no-memory-check"])
last = R.last_line(output)
C.check(code == 1 and last.startswith("error: reduction failed: DimensionReduction needs") and
        "available" in last,
        "a filter's memory check stops the job with its message: %d %s" % (code, last))
C.check(R.content(out) == before, "memory errors: the previous output as it was")

# Address-space limits (ulimit -v): a clean refusal or success, never a crash. The job as
# scripts/run-main.sh starts it (scripts/main-job.sh): under 0.5 GB pvbatch cannot even map
# its libraries, which the launcher's trial start turns into the job's own message.
LAUNCHER = [os.path.join(T.REPO, "scripts", "main-job.sh")] + job_command(out)[2:]
for gb in (0.5, 1.0, 1.5, 2.0, 4.0):
    label = "ulimit -v %g GB" % gb
    code, output, _ = R.run(["bash"] + LAUNCHER, memory_limit=int(gb * (1 << 30)))
    last = R.last_line(output)
    before = R.ran_or_refused(out, C, label, code, last, last.startswith("error:") and
                              "needs" in last and "available" in last,
                              "the memory it needs", before)

# Full disk at several fill levels, and read-only.
disk = R.mounted_tmpfs(work, 8192, "full-disk and read-only cases")
if disk is not None:
    try:
        small = os.path.join(disk.folder, "out")
        complete_run(small, "tmpfs: complete run")
        if not os.path.isdir(small):
            C.finish()
        need = sum(os.path.getsize(os.path.join(small, n)) for n in os.listdir(small))
        print("the outputs take %d KiB" % (need // 1024))
        previous = R.content(small)
        for leave in (16 << 10, need // 3, 2 * need // 3, 4 * need // 5, need - (8 << 10),
                      need + (256 << 10)):
            free = disk.fill(leave)
            label = "tmpfs with %d KiB free" % (free // 1024)
            code, output, _ = run_job(small)
            message = R.last_line(output)
            previous = R.ran_or_refused(small, C, label, code, message, "disk full" in message and
                                        ("was not written" in message or
                                         "the outputs need" in message), "the cause", previous)
            R.no_staging_left(disk.folder, "out", C, label)
        disk.unfill()
        if C.check(disk.remount("ro"), "tmpfs remounted read-only"):
            code, output, _ = run_job(small)
            message = R.last_line(output)
            C.check(code == 1 and "read-only file system" in message and
                    "\nread " not in "\n" + output,
                    "read-only: exit code 1 before anything is read: %s" % message)
            C.check(R.content(small) == previous, "read-only: the previous output as it was")
    finally:
        disk.close()
C.finish()
