"""Outputs of batch jobs that never lie: what the main job (transfer_function.py) and the
snapshot tool (snapshot_collection.py) use to write their results under full disks,
read-only folders, signals and filter errors.

- RunFolder: a job writes into a fresh staging folder beside its output folder
  (PARENT/.NAME.run-PID) and switches it in only at the end, in one atomic exchange of the
  two folders (renameat2 RENAME_EXCHANGE): the output folder holds either the previous
  complete run or the new complete one, never a mix. A lock (PARENT/.NAME.lock, flock)
  keeps a second job off the same output; staging folders of killed runs are removed by
  the next one.
- Each file is written to a temporary name, checked (a PNG decodes at its size, a JSON
  parses) and renamed into place; a file that was not written is an error naming the file
  and the cause: disk full, read-only file system or permission denied (VTK's PNG writer
  says "Ran out of disk space" for all of them).
- StopSignals: SIGINT / SIGTERM set a flag that the filters' progress observers turn into
  their abort (AbortExecute), and that the job turns into Interrupted at its next check.
- VtkErrors: the error messages VTK objects report (out of memory, "needs X GiB"), so that a
  stage that failed stops the job instead of feeding an empty output to the next one.

Import it from an example with ``sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))``.
"""
import ctypes
import errno
import fcntl
import json
import os
import shutil
import signal

EXIT_ERROR = 1


class JobError(Exception):
    """A failure the job reports as one line and exit code 1."""


class Interrupted(Exception):
    """SIGINT or SIGTERM arrived; exit code 128 + signal number (130, 143)."""

    def __init__(self, signum):
        Exception.__init__(self, "interrupted by %s" % signal.Signals(signum).name)
        self.signum = signum
        self.exit_code = 128 + signum


class Locked(JobError):
    """Another run holds the output folder's lock."""


# ---------------------------------------------------------------------------------------
# Why a write failed.

_CAUSES = {errno.ENOSPC: "disk full", errno.EDQUOT: "disk quota exceeded",
           errno.EROFS: "read-only file system", errno.EACCES: "permission denied",
           errno.EPERM: "permission denied"}


def cause_of(error):
    """'disk full', 'read-only file system', 'permission denied' or the OS's words for an
    OSError."""
    return _CAUSES.get(getattr(error, "errno", None)) or (
        error.strerror if getattr(error, "strerror", None) else str(error))


def is_disk_full(error):
    return getattr(error, "errno", None) in (errno.ENOSPC, errno.EDQUOT)


def free_bytes(folder):
    """Bytes an unprivileged writer can still put into `folder`'s file system."""
    st = os.statvfs(folder)
    return st.f_bavail * st.f_frsize


def _human(n):
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n >= size:
            return "%.1f %s" % (n / float(size), unit)
    return "%d B" % n


def probe_write(folder, nbytes=65536):
    """Writes and removes `nbytes` in `folder`; returns None when that worked, else the
    OSError (its errno tells disk full from read-only from permission denied). Used after a
    writer that does not say why it failed (VTK's), and before a job starts."""
    path = os.path.join(folder, ".write-probe-%d" % os.getpid())
    try:
        with open(path, "wb") as f:
            block = b"\0" * min(nbytes, 1 << 20)
            left = nbytes
            while left > 0:
                f.write(block[:left])
                left -= len(block)
            f.flush()
            os.fsync(f.fileno())
        return None
    except OSError as exc:
        return exc
    finally:
        try:
            os.remove(path)
        except OSError:
            pass


def write_failure(name, folder, detail=None):
    """JobError for a file `name` that was not written into `folder`, with the cause found
    by a probe write (or from the file system's flags when the probe succeeds now, e.g.
    after the failed writer removed its partial file)."""
    exc = probe_write(folder)
    if exc is not None:
        cause = cause_of(exc)
    else:
        try:
            st = os.statvfs(folder)
            cause = "read-only file system" if st.f_flag & os.ST_RDONLY else (
                "disk full" if free_bytes(folder) < (1 << 20) else None)
        except OSError as stat_error:
            cause = cause_of(stat_error)
    if cause is None:
        cause = "the writer failed" + (": %s" % detail if detail else "")
    try:
        room = ", %s free" % _human(free_bytes(folder)) if cause.startswith("disk") else ""
    except OSError:
        room = ""
    return JobError("%s was not written in %s: %s%s" % (name, folder, cause, room))


# ---------------------------------------------------------------------------------------
# Checked files.

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
# Samples per pixel of each PNG colour type (grey, RGB, palette, grey+alpha, RGBA).
_PNG_CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


def check_png(path, size=None):
    """None when `path` is a complete PNG (at `size` = (width, height) when given), else
    what is wrong with it. Every chunk's CRC is checked, the image data is inflated (zlib)
    and must hold exactly the rows IHDR announces, and the file must end with IEND.
    Checked here with the standard library rather than vtkPNGReader, which crashes the
    process (libpng's error longjmp) on a file cut short, the very case to find."""
    import struct
    import zlib

    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as exc:
        return "missing" if not os.path.exists(path) else "unreadable (%s)" % cause_of(exc)
    if not data:
        return "empty (0 bytes)"
    if not data.startswith(_PNG_SIGNATURE):
        return "not a PNG"
    pos, header, idat, ended = len(_PNG_SIGNATURE), None, [], False
    while pos + 12 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        crc = data[pos + 8 + length:pos + 12 + length]
        if len(body) != length or len(crc) != 4:
            return "truncated (inside its %s chunk)" % kind.decode("latin-1")
        if zlib.crc32(kind + body) & 0xffffffff != struct.unpack(">I", crc)[0]:
            return "corrupt (bad CRC of its %s chunk)" % kind.decode("latin-1")
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            ended = True
            break
        pos += 12 + length
    if header is None:
        return "corrupt (no IHDR chunk)"
    if not ended:
        return "truncated (no IEND chunk)"
    width, height, depth, colour, _, _, interlace = header
    try:
        pixels = zlib.decompress(b"".join(idat))
    except zlib.error as exc:
        return "does not decode (%s)" % exc
    if not interlace and colour in _PNG_CHANNELS:
        row = 1 + (width * _PNG_CHANNELS[colour] * depth + 7) // 8
        if len(pixels) != row * height:
            return "does not decode (%d bytes of pixels instead of %d)" % (
                len(pixels), row * height)
    if size is not None and (width, height) != (int(size[0]), int(size[1])):
        return "%dx%d pixels instead of %dx%d" % (width, height, size[0], size[1])
    return None


def check_json(path):
    """None when `path` parses as JSON, else what is wrong with it."""
    try:
        with open(path) as f:
            json.load(f)
    except (OSError, ValueError) as exc:
        return "does not parse (%s)" % exc
    return None


def _write_replacing(path, text, check=None):
    """Writes `text` to PATH.part, runs check(tmp) (a problem text or None), renames it to
    `path`. OSError (ENOSPC, EROFS, EACCES) becomes a JobError naming the file and the
    cause; the temporary file never stays."""
    tmp = path + ".part"
    try:
        with open(tmp, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        problem = check(tmp) if check else None
        if problem:
            raise JobError("%s: %s" % (os.path.basename(path), problem))
        os.replace(tmp, path)
    except OSError as exc:
        _remove(tmp)
        raise JobError("%s was not written in %s: %s" % (
            os.path.basename(path), os.path.dirname(os.path.abspath(path)), cause_of(exc)))
    except BaseException:
        _remove(tmp)
        raise


def write_json(path, data):
    """Writes `data` to PATH.part, reads it back, renames it to `path` (_write_replacing)."""
    _write_replacing(path, json.dumps(data, indent=2), check_json)


def write_text(path, text):
    """As write_json for a text file (an HTML page)."""
    _write_replacing(path, text)


def checked_png(path, write, size=None):
    """Runs write(tmp) (a SaveScreenshot or a matplotlib savefig into a temporary name
    beside `path`), checks the PNG (decodes, at `size` when given) and renames it to `path`.
    A missing or invalid picture is a JobError with the cause (disk full, read-only,
    permission denied); the temporary file is removed."""
    folder = os.path.dirname(os.path.abspath(path))
    name = os.path.basename(path)
    tmp = os.path.join(folder, "." + name + ".part.png")
    try:
        try:
            write(tmp)
        except OSError as exc:  # matplotlib, Python writers: the OS's own errno
            raise JobError("%s was not written in %s: %s" % (name, folder, cause_of(exc)))
        problem = check_png(tmp, size)
        if problem:
            _remove(tmp)  # the partial file's room counts for the probe write's verdict
            raise write_failure(name, folder, problem)
        os.replace(tmp, path)
    finally:
        _remove(tmp)


def _remove(path):
    try:
        os.remove(path)
    except OSError:
        pass


# ---------------------------------------------------------------------------------------
# The output folder: lock, staging, exchange.

def _exchange(a, b):
    """Atomically swaps the names of two directories (renameat2 RENAME_EXCHANGE, Linux 3.15,
    glibc 2.28). Returns False where the call is not available (then the caller renames
    twice)."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p,
                          ctypes.c_uint]
    AT_FDCWD, RENAME_EXCHANGE = -100, 2
    if renameat2(AT_FDCWD, os.fsencode(a), AT_FDCWD, os.fsencode(b), RENAME_EXCHANGE) != 0:
        err = ctypes.get_errno()
        if err in (errno.ENOSYS, errno.EINVAL):
            return False
        raise OSError(err, os.strerror(err), a)
    return True


def lock_file(path, what):
    """Takes an exclusive flock on `path` (created, holding the holder's pid) without
    waiting; returns the open file (keep it: closing it releases the lock). Locked names
    the other run's pid when the lock is held."""
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as exc:
        raise JobError("cannot create the lock file %s: %s" % (path, cause_of(exc)))
    handle = os.fdopen(fd, "r+")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as exc:
        if exc.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
            raise
        handle.seek(0)
        holder = handle.read().strip()
        handle.close()
        raise Locked("%s is in use by another run%s (lock %s): wait for it to finish or "
                     "choose another output folder" % (
                         what, " (pid %s)" % holder if holder else "", path))
    try:
        handle.seek(0)
        handle.truncate()
        handle.write("%d\n" % os.getpid())
        handle.flush()
    except OSError:
        pass  # a full disk: the lock holds all the same, only the pid is not written
    return handle


class RunFolder(object):
    """The output folder of one run, written in a staging folder and switched in by commit().

        run = RunFolder("output/transfer_function")   # lock, staging folder
        ...  write into run.path("best.png") ...
        run.commit()       # the staging folder becomes output/transfer_function
        # or run.abandon(): the staging folder is removed, the old output stays as it was

    Only the job's own `names` are moved over from a previous output; anything else the
    user put into the output folder is carried over into the new one.
    """

    def __init__(self, output, min_free_bytes=0):
        self.output = os.path.abspath(output)
        parent, base = os.path.split(self.output)
        self.parent = parent
        try:
            os.makedirs(parent, exist_ok=True)
        except OSError as exc:
            raise JobError("cannot create the output folder's parent %s: %s"
                           % (parent, cause_of(exc)))
        self._lock = lock_file(os.path.join(parent, "." + base + ".lock"),
                               "the output folder %s" % self.output)
        self._prefix = "." + base + ".run-"
        self._remove_stale()
        self.staging = os.path.join(parent, "%s%d" % (self._prefix, os.getpid()))
        try:
            os.mkdir(self.staging)
        except OSError as exc:
            self.release()
            raise JobError("cannot write into %s (the output folder's parent, where the run "
                           "is written before it replaces %s): %s"
                           % (parent, base, cause_of(exc)))
        exc = probe_write(self.staging, max(4096, min(min_free_bytes, 1 << 20)))
        room = free_bytes(self.staging)
        if exc is not None or room < min_free_bytes:
            self.abandon()
            full = exc is None or is_disk_full(exc)
            raise JobError("cannot write the results into %s: %s" % (
                parent, "%s (%s free, the outputs need about %s)"
                % (cause_of(exc) if exc is not None else "disk full", _human(room),
                   _human(min_free_bytes)) if full else cause_of(exc)))
        self.committed = False

    def _remove_stale(self):
        """Staging folders of runs that were killed (the lock says none is running)."""
        try:
            names = os.listdir(self.parent)
        except OSError:
            return
        for n in names:
            if n.startswith(self._prefix):
                shutil.rmtree(os.path.join(self.parent, n), ignore_errors=True)

    def path(self, name):
        return os.path.join(self.staging, name)

    def final(self, name):
        return os.path.join(self.output, name)

    def commit(self, own_names):
        """Switches the staging folder in as the output folder. `own_names`: what this job
        writes (the previous run's copies are dropped); other entries of the old folder are
        moved into the new one. Signals are held back meanwhile."""
        old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        try:
            if os.path.isdir(self.output):
                for n in os.listdir(self.output):
                    if n not in own_names and not os.path.exists(self.path(n)):
                        os.rename(os.path.join(self.output, n), self.path(n))
                if not _exchange(self.staging, self.output):
                    aside = self.staging + ".old"
                    os.rename(self.output, aside)
                    os.rename(self.staging, self.output)
                    os.rename(aside, self.staging)
            else:
                os.rename(self.staging, self.output)
            self.committed = True
        finally:
            shutil.rmtree(self.staging, ignore_errors=True)  # now the previous run
            self.release()
            signal.pthread_sigmask(signal.SIG_SETMASK, old)

    def abandon(self):
        """Removes the staging folder; the output folder stays as it was."""
        shutil.rmtree(self.staging, ignore_errors=True)
        self.release()

    def release(self):
        if self._lock is not None:
            self._lock.close()
            self._lock = None


# ---------------------------------------------------------------------------------------
# Signals and VTK errors.

class signals_held(object):
    """with signals_held(): SIGINT and SIGTERM wait until the block is done (a file rename
    or an index write is then never cut in half by them)."""

    def __enter__(self):
        self._old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})

    def __exit__(self, *exc):
        signal.pthread_sigmask(signal.SIG_SETMASK, self._old)
        return False


class StopSignals(object):
    """SIGINT and SIGTERM set `signum` instead of ending the process at once. Python runs the
    handler at its next bytecode: between stages, or inside a filter when the filter's
    progress observer (watch()) is called, which then sets the filter's AbortExecute so
    that it stops at that progress report."""

    def __init__(self, signum=None):
        self.signum = signum  # one that came before (the script's own early handler)
        self._previous = {}
        for s in (signal.SIGINT, signal.SIGTERM):
            self._previous[s] = signal.signal(s, self._handle)

    def _handle(self, signum, frame):
        if self.signum is None:
            self.signum = signum

    def check(self):
        if self.signum is not None:
            raise Interrupted(self.signum)

    def watch(self, proxy):
        """Aborts `proxy`'s algorithm at its next progress report once a signal came."""
        algorithm = proxy.GetClientSideObject() if hasattr(proxy, "GetClientSideObject") \
            else proxy

        def on_progress(caller, event):
            if self.signum is not None:
                caller.SetAbortExecute(1)

        algorithm.AddObserver("ProgressEvent", on_progress)
        return proxy

    def restore(self):
        for s, handler in self._previous.items():
            signal.signal(s, handler)


class VtkErrors(object):
    """Error messages of VTK objects (through vtkOutputWindow, as ParaView shows them) since
    the last take(): "<Class>: <message>", the pipeline's follow-ups ("... returned failure
    for request") left out."""

    def __init__(self):
        from vtkmodules.util.misc import calldata_type
        from vtkmodules.util.vtkConstants import VTK_STRING
        from vtkmodules.vtkCommonCore import vtkOutputWindow

        self.messages = []

        @calldata_type(VTK_STRING)
        def on_error(caller, event, text):
            # pvbatch sends Python's sys.stderr through the output window too: only VTK's
            # own errors ("ERROR: In file, line N" then "vtkClass (0x...): message") count.
            # Nothing may raise here: the traceback would go to sys.stderr, hence here again.
            try:
                lines = [l for l in str(text).strip().splitlines() if l.strip()]
                if len(lines) < 2 or not lines[0].startswith("ERROR: In "):
                    return
                source, _, message = lines[1].partition("): ")
                if not source.split(" ")[0].endswith(("Pipeline", "Executive")):
                    self.messages.append(" ".join([message or source] + lines[2:]).strip())
            except Exception:  # noqa: BLE001 (see above)
                pass

        self._callback = on_error
        self._window = vtkOutputWindow.GetInstance()
        self._tag = self._window.AddObserver("ErrorEvent", on_error)

    def take(self):
        messages, self.messages = self.messages, []
        return messages

    def stop(self):
        self._window.RemoveObserver(self._tag)


# ---------------------------------------------------------------------------------------
# Memory.

def gib(n):
    return "%.2f GiB" % (n / float(1 << 30))


def _proc_kib(path, key):
    """The "KEY: N kB" line of a /proc file as bytes, or None."""
    try:
        with open(path) as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError):
        pass
    return None


def _meminfo(key):
    return _proc_kib("/proc/meminfo", key)


def _vm_size(key="VmSize"):
    """The process's virtual size (VmSize), or its peak so far (key "VmPeak"), in bytes."""
    return _proc_kib("/proc/self/status", key)


def _cgroup_room():
    """What the process's cgroup (v2) limit leaves, or None."""
    try:
        with open("/proc/self/cgroup") as f:
            path = next((l.strip().split(":", 2)[2] for l in f if l.startswith("0::")), None)
        if path is None:
            return None
        folder = os.path.join("/sys/fs/cgroup", path.lstrip("/"))
        with open(os.path.join(folder, "memory.max")) as f:
            limit = f.read().strip()
        if limit == "max":
            return None
        with open(os.path.join(folder, "memory.current")) as f:
            return max(0, int(limit) - int(f.read().strip()))
    except (OSError, ValueError, StopIteration):
        return None


def available_memory():
    """Bytes this process may still allocate, as the plugin's filters count them
    (MemoryBudget.h): MCV_MEMORY_LIMIT_MB when set, else MemAvailable lowered to what the
    cgroup limit and the address-space limit (ulimit -v, above the current virtual size)
    leave. None when nothing says."""
    import resource

    forced = os.environ.get("MCV_MEMORY_LIMIT_MB")
    if forced:
        try:
            if float(forced) >= 0:
                return int(float(forced) * (1 << 20))
        except ValueError:
            pass
    room = [r for r in (_meminfo("MemAvailable"), _cgroup_room()) if r is not None]
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    size = _vm_size()
    if soft != resource.RLIM_INFINITY and size is not None:
        room.append(max(0, soft - size))
    return min(room) if room else None


# Rendering's and the figures' share of the address space, beyond the voxels: the GL
# context (Mesa's llvmpipe: its threads' stacks and LLVM), the render windows' buffers,
# matplotlib: pvbatch's VmSize roughly doubles (by about 0.9 GB under Xvfb) when it opens
# a 240 x 180 render view and renders; with less address space left,
# VTK aborts the process ("Cannot create GLX context. Aborting.", exit 134), so the job must
# refuse before that. See docs/reliability.md.
RENDER_SHARE_BYTES = 1 << 30


def job_memory_bytes(read_voxels, voxels, channels, features, features_chain,
                     half_coordinates, size, methods, methods_stride):
    """The main job's estimated peak beyond what the process holds when it starts, in bytes:
    per voxel read, the channels as read and merged (4 bytes each, twice); per voxel of the
    chain (after --upsample), the resampled channels (4 bytes each, when resampled), the
    Features array (--chain features), the reduced coordinates (12 or 6 bytes), the
    foreground mask and the sample's strata (2), the best viewpoint's opacity and Harris
    response (8), the volume mapper's copy of the coordinates as a texture (12) and the
    widgets' opacity (4); the methods' coarse grid (its share of that); and the rendering
    share (RENDER_SHARE_BYTES and the screenshots' buffers)."""
    per_voxel = ((4 * channels if voxels != read_voxels else 0)
                 + (4 * features if features_chain else 0)
                 + (6 if half_coordinates else 12) + 2 + 8 + 12 + 4)
    total = read_voxels * 8 * channels + voxels * per_voxel
    if methods:
        total += voxels * per_voxel // max(1, methods_stride) ** 3
    total += 4 * 4 * 2 * size[0] * size[1] + RENDER_SHARE_BYTES
    return int(total)
