"""Where a student's code runs: the grader compiles and runs every submission through
Sandbox.run, never directly.

As root (Gradescope, a CI job, sudo ./course grade), a submission runs as a dedicated
unprivileged user, course-grader (course-grader1, course-grader2, ... when several
submissions are graded at once: each user is locked by one grading at a time, so
"every process of that user" is that submission's processes and nothing else):

- no network, IPC or shared folders: new network, IPC and mount namespaces where the
  kernel allows them (not even loopback is up; /tmp, /var/tmp, /dev/shm and /run/lock
  are private and small; the instructor's folders are covered by an empty, read-only
  tmpfs);
- file permissions: the instructor's tree is closed to other users (chmod o-rwx); the
  grading's scratch folder belongs to root and the user's group, its work folder to
  the user; what compiling needs comes from a read-only staging copy outside the tree;
- no supplementary groups, no capabilities (the bounding set is emptied) and
  no_new_privs (a set-user-ID program gains nothing);
- limits per process (setrlimit): CPU seconds, address space, processes of the user,
  file size, open files, no core files; per run, watched from outside: wall time,
  output size, bytes left in its folder;
- after every run, every process of the user is killed (kill(-1) as that user: atomic
  against fork, so a fork bomb goes too), and what it left in the shared temporary
  folders (when they are not private) is removed. Only then does the grader read
  what the run wrote.

Not root, the submission runs as the grader's own user: the limits hold, and where
unprivileged user namespaces are allowed so do the namespaces (hiding the instructor's
folders), but file permissions cannot keep anything from it. protections() says
which of these were in force, for the report.
"""

from __future__ import annotations

import contextvars
import fcntl
import json
import os
import pwd
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, fields
from pathlib import Path
from typing import NamedTuple

USER = "course-grader"      # slot 0; slot n is course-grader<n>
MAX_SLOTS = 32
SHARED_TEMP = ("/tmp", "/var/tmp", "/dev/shm", "/run/lock")
PRIVATE_TEMP_MB = 64
OUTPUT_KEPT = 20_000        # characters of a run's output kept for the report
SAFE_PATH = "/usr/local/bin:/usr/bin:/bin"


class SandboxError(Exception):
    """The sandbox cannot be set up as promised: grading must not go on."""


# The chapters' GPU watchdog (common/gpu_watchdog.h) ends a render whose GPU finishes no
# step for 30 s. A step's time includes the driver's shader compilation the first time
# (llvmpipe compiles at the first dispatch: chapter 18's megakernel 5 s on Mesa 22 alone),
# and a grading runs beside others (a class, or the suite's catalogues two at a time on
# each core): on Mesa 25 under that load (Debian 13, 2026-12-04), two correct submissions
# of chapter 18 ended with the GL's exit code 4 in the first run of their first test, the
# one that compiles the shaders, and in no later run (those read Mesa's shader cache).
# A grading's runs allow a step 120 s, under the run's wall limit, which guards the rest.
GRADING_GPU_STEP_SECONDS = 120


@dataclass(frozen=True)
class Limits:
    """Per run. The environment may lower them (the course's own tests of the grader
    do, to keep hostile submissions short): COURSE_GRADE_<FIELD>, e.g.
    COURSE_GRADE_WALL_SECONDS=5."""
    cpu_seconds: int = 120      # per process; SIGXCPU, then SIGKILL 5 s later
    wall_seconds: int = 180     # per run of the program (a hung GPU or driver too)
    compile_seconds: int = 300  # per compiler or linker run
    # All of one grading's compiles and runs: what is left when it is spent scores 0,
    # so a crawling submission still gets its results before Gradescope's time-out
    # (10 minutes unless the instructor sets more) ends the autograder with none.
    total_seconds: int = 480
    memory_mb: int = 4096       # address space per process (llvmpipe needs ~1 GiB)
    processes: int = 128        # processes and threads of the user at once
    file_mb: int = 256          # any one file it writes
    open_files: int = 1024
    output_mb: int = 64         # stdout + stderr of a run
    disk_mb: int = 1024         # everything in its work folder

    @classmethod
    def from_environment(cls) -> Limits:
        values = {}
        for field in fields(cls):
            variable = f"COURSE_GRADE_{field.name.upper()}"
            if os.environ.get(variable):
                values[field.name] = int(os.environ[variable])
        return cls(**values)

    def rlimits(self, cpu_seconds: int) -> dict[str, tuple[int, int]]:
        mib = 1 << 20
        return {"RLIMIT_CPU": (cpu_seconds, cpu_seconds + 5),
                "RLIMIT_AS": (self.memory_mb * mib,) * 2,
                "RLIMIT_NPROC": (self.processes,) * 2,
                "RLIMIT_FSIZE": (self.file_mb * mib,) * 2,
                "RLIMIT_NOFILE": (self.open_files,) * 2,
                "RLIMIT_CORE": (0, 0)}

    def describe(self) -> str:
        return (f"{self.cpu_seconds} s of CPU per process, {self.wall_seconds} s of wall "
                f"time per run ({self.compile_seconds} s to compile a file; "
                f"{self.total_seconds} s for the whole grading), "
                f"{self.memory_mb} MiB of address space per process, {self.processes} "
                f"processes and threads, {self.file_mb} MiB per file, {self.open_files} "
                f"open files, {self.output_mb} MiB of output, {self.disk_mb} MiB in its "
                "folder, no core files")


class Run(NamedTuple):
    """code: the exit code, minus the signal number when a signal ended it, None when
    the wall clock ran out, "total" when the grading's whole time did (or had: the run
    was not started), "output" or "disk" when it wrote too much. A named pair, so that
    `code, output = run_limited(...)` reads it too."""
    code: int | str | None
    output: str


# The first thing a sandboxed run executes, as root (or as the grader's user) inside the
# new namespaces: covers folders, sets the limits, drops every privilege, then execs the
# command. Passed with -c, so that nothing it needs is in a folder it hides; everything
# it imports is imported before the first mount.
LAUNCHER = r"""
import ctypes, json, os, resource, sys
spec, command = json.loads(sys.argv[1]), sys.argv[2:]
libc = ctypes.CDLL(None, use_errno=True)
program = command[0]
if "/" not in program:  # searched now: after the user changes, no more imports
    folders = os.environ.get("PATH", "/usr/bin:/bin").split(":")
    found = [os.path.join(f, program) for f in folders
             if os.access(os.path.join(f, program), os.X_OK)]
    program = found[0] if found else program
def fail(what):
    sys.stderr.write(f"sandbox: {what}: {os.strerror(ctypes.get_errno())}\n")
    sys.exit(125)
def mount(target, flags, options):
    if libc.mount(b"tmpfs", target.encode(), b"tmpfs", ctypes.c_ulong(flags),
                  options.encode()) != 0:
        fail(f"mounting a tmpfs on {target}")
MS_RDONLY, MS_NOSUID, MS_NODEV, MS_NOEXEC, MS_REC, MS_PRIVATE = 1, 2, 4, 8, 1 << 14, 1 << 18
if spec["mount"]:
    if libc.mount(None, b"/", None, ctypes.c_ulong(MS_REC | MS_PRIVATE), None) != 0:
        fail("making mounts private")
    for path in spec["private_temp"]:
        mount(path, MS_NOSUID | MS_NODEV, f"size={spec['temp_mb']}m,mode=1777")
    for path in spec["hide"]:
        mount(path, MS_RDONLY | MS_NOSUID | MS_NODEV | MS_NOEXEC, "size=4k,mode=0555")
for name, value in spec["limits"].items():
    resource.setrlimit(getattr(resource, name), tuple(value))
PR_CAPBSET_DROP, PR_SET_SECUREBITS, PR_SET_NO_NEW_PRIVS = 24, 28, 38
cap = 0
while libc.prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) == 0:
    cap += 1
libc.prctl(PR_SET_SECUREBITS, 0x3, 0, 0, 0)  # NOROOT, locked: uid 0 gains no caps by exec
if spec["uid"] is not None:
    os.setgroups([])
    os.setgid(spec["gid"])
    os.setuid(spec["uid"])
if libc.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0:
    fail("no_new_privs")
try:
    os.execv(program, command)
except OSError as error:
    sys.stderr.write(f"sandbox: cannot run {command[0]}: {error.strerror}\n")
    sys.exit(126)
"""

# Run as the sandbox's user: kill(-1) reaches every process of that user and nothing
# else, in one step the kernel does not interleave with fork().
KILLER = r"""
import os, sys
os.setgroups([]); os.setgid(int(sys.argv[2])); os.setuid(int(sys.argv[1]))
try:
    os.kill(-1, 9)
except ProcessLookupError:
    pass
"""

PYTHON = os.path.realpath(sys.executable)
_ACTIVE: contextvars.ContextVar[Sandbox | None] = contextvars.ContextVar("sandbox",
                                                                       default=None)
_NAMESPACES: dict[bool, list[str]] = {}


def active() -> Sandbox | None:
    """The sandbox of the grading this thread is doing, if any."""
    return _ACTIVE.get()


def is_root() -> bool:
    return os.geteuid() == 0


def default_base() -> Path:
    if os.environ.get("COURSE_GRADE_SCRATCH"):
        return Path(os.environ["COURSE_GRADE_SCRATCH"])
    if is_root():
        return Path("/var/lib/course-grader")
    return Path(tempfile.gettempdir()) / f"course-grader-{os.getuid()}"


def prepare_base(base: Path) -> Path:
    """The folder that holds scratch folders, the staging copies and the slot locks:
    others may pass through it (to their own scratch folder) but not list it."""
    base.mkdir(parents=True, exist_ok=True)
    os.chmod(base, 0o711 if is_root() else 0o700)
    return base


def namespaces() -> list[str]:
    """The unshare options this kernel allows us: as root --net --ipc --mount; not root,
    the same inside a new user namespace, if unprivileged ones are allowed."""
    root = is_root()
    if root not in _NAMESPACES:
        candidates = [["--net", "--ipc", "--mount"], ["--net", "--ipc"], ["--net"]]
        prefix = [] if root else ["--user", "--map-root-user"]
        _NAMESPACES[root] = []
        if shutil.which("unshare"):
            for option in candidates:
                probe = subprocess.run(["unshare", *prefix, *option, "true"],
                                       capture_output=True)
                if probe.returncode == 0:
                    _NAMESPACES[root] = prefix + option
                    break
    return _NAMESPACES[root]


def _ensure_user(name: str, locks: Path) -> tuple[int, int]:
    try:
        entry = pwd.getpwnam(name)
    except KeyError:
        with open(locks / "useradd.lock", "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                entry = pwd.getpwnam(name)
            except KeyError:
                if not shutil.which("useradd"):
                    raise SandboxError(f"there is no user {name} and no useradd to make "
                                       "one: create a system user without a home or "
                                       "login shell by that name") from None
                shell = "/usr/sbin/nologin" if os.path.exists("/usr/sbin/nologin") \
                    else "/bin/false"
                made = subprocess.run(["useradd", "--system", "--no-create-home",
                                       "--home-dir", "/nonexistent", "--shell", shell,
                                       "--user-group", name], capture_output=True, text=True)
                if made.returncode != 0:
                    raise SandboxError(f"useradd {name} failed: {made.stderr.strip()}")
                entry = pwd.getpwnam(name)
    if entry.pw_uid == 0 or entry.pw_gid == 0:
        raise SandboxError(f"the user {name} must not be root or in root's group")
    return entry.pw_uid, entry.pw_gid


def _live_processes(uid: int, zombies: bool = False) -> list[int] | None:
    """Processes whose real or effective user is uid, zombies left out unless asked for
    (their parent or init reaps them; they run nothing, but until then they count
    towards the user's process limit); None without /proc."""
    if not os.path.exists("/proc/self/status"):
        return None
    found = []
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit():
            continue
        try:
            with open(f"/proc/{entry.name}/status") as status:
                text = status.read()
        except OSError:
            continue
        fields_ = dict(line.split(":", 1) for line in text.splitlines() if ":" in line)
        ids = fields_.get("Uid", "").split()
        zombie = fields_.get("State", "").strip().startswith("Z")
        ours = fields_.get("PPid", "").strip() == str(os.getpid())  # we reap those
        if str(uid) in ids[:2] and (not zombie or (zombies and not ours)):
            found.append(int(entry.name))
    return found


class Sandbox:
    """One grading's sandbox: `with Sandbox(hide=[...]) as box:` acquires a user, makes a
    scratch folder, and makes itself the one run_limited uses in this thread."""

    def __init__(self, hide=(), close=(), limits: Limits | None = None,
                 base: Path | None = None):
        self.limits = limits or Limits.from_environment()
        self.base = base or default_base()
        self.requested_hide = [Path(p) for p in hide]
        self.close = [Path(p) for p in close]
        self.root = is_root()
        self.user, self.uid, self.gid = None, None, None
        self.closed: list[Path] = []
        self._lock = None
        self.ends = None  # monotonic time when the grading's total_seconds are spent

    # ---------------------------------------------------------------- set-up

    def __enter__(self) -> Sandbox:
        prepare_base(self.base)
        locks = self.base / "slots"
        locks.mkdir(exist_ok=True)
        os.chmod(locks, 0o700)
        slot, self._lock = self._acquire_slot(locks)
        if self.root:
            self.user = USER if slot == 0 else f"{USER}{slot}"
            self.uid, self.gid = _ensure_user(self.user, locks)
            for path in self.close:
                mode = path.stat().st_mode & 0o7777
                if mode & 0o007:
                    os.chmod(path, mode & ~0o007)
                    self.closed.append(path)
        self.namespaces = namespaces()
        self.mount = "--mount" in self.namespaces
        # One scratch folder per slot, emptied for each grading: its path is compiled into
        # the program (COURSE_SHADER_DIR), so the same one makes the same object.
        self.scratch = self.base / f"slot{slot}"
        shutil.rmtree(self.scratch, ignore_errors=True)
        self.scratch.mkdir()
        if self.root:
            os.chown(self.scratch, 0, self.gid)
            os.chmod(self.scratch, 0o710)
        self.private_temp = [p for p in SHARED_TEMP if os.path.isdir(p) and
                             not os.path.islink(p) and not self._contains(Path(p))]
        self.hide = self._hideable(self.requested_hide)
        self.kill_all()
        self._sweep_shared_temp()
        self._token = _ACTIVE.set(self)
        self.ends = time.monotonic() + self.limits.total_seconds
        return self

    def __exit__(self, *exc):
        try:
            self.kill_all()
            self._sweep_shared_temp()
        finally:
            _ACTIVE.reset(self._token)
            shutil.rmtree(self.scratch, ignore_errors=True)
            if self._lock:
                self._lock.close()

    @staticmethod
    def _acquire_slot(locks: Path):
        while True:
            for slot in range(MAX_SLOTS):
                handle = open(locks / f"{slot}.lock", "a")
                try:
                    fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    return slot, handle
                except BlockingIOError:
                    handle.close()
            time.sleep(0.5)

    def _contains(self, path: Path) -> bool:
        """Is the scratch folder at or under path (so that covering path would hide it)?"""
        path = path.resolve()
        return path == self.scratch.resolve() or path in self.scratch.resolve().parents

    def _hideable(self, paths: list[Path]) -> list[str]:
        """Folders a tmpfs can cover: existing, not holding the scratch folder, not
        inside another covered one or a private temporary folder."""
        kept: list[Path] = []
        covered = [Path(p) for p in self.private_temp] if self.mount else []
        for path in sorted({p.resolve() for p in paths}, key=lambda p: len(p.parts)):
            if not path.is_dir() or path == Path("/") or self._contains(path):
                continue
            if any(path == c or c in path.parents for c in covered + kept):
                continue
            kept.append(path)
        return [str(p) for p in kept]

    # ---------------------------------------------------------------- folders

    def folder(self, name: str, writable: bool) -> Path:
        """A folder of the scratch: writable ones belong to the sandbox's user; the
        others to root, readable by the user's group only."""
        path = self.scratch / name
        path.mkdir()
        if self.root:
            if writable:
                os.chown(path, self.uid, self.gid)
                os.chmod(path, 0o700)
            else:
                os.chown(path, 0, self.gid)
                os.chmod(path, 0o750)
        return path

    def seal(self, folder: Path):
        """Makes what root copied into a read-only folder readable to the user only."""
        if not self.root:
            return
        for directory, subdirectories, files in os.walk(folder):
            for name in subdirectories:
                os.lchown(os.path.join(directory, name), 0, self.gid)
                os.chmod(os.path.join(directory, name), 0o750)
            for name in files:
                os.lchown(os.path.join(directory, name), 0, self.gid)
                os.chmod(os.path.join(directory, name), 0o640)

    # ---------------------------------------------------------------- running

    def command(self, argv: list[str], cpu_seconds: int) -> list[str]:
        spec = {"mount": self.mount, "private_temp": self.private_temp if self.mount else [],
                "temp_mb": PRIVATE_TEMP_MB, "hide": self.hide if self.mount else [],
                "limits": self.limits.rlimits(cpu_seconds), "uid": self.uid, "gid": self.gid}
        launcher = [PYTHON, "-I", "-S", "-c", LAUNCHER, json.dumps(spec), *argv]
        return (["unshare", *self.namespaces, "--"] if self.namespaces else []) + launcher

    def environment(self, cwd: Path) -> dict[str, str]:
        env = {"PATH": SAFE_PATH, "HOME": str(cwd), "TMPDIR": str(cwd), "LANG": "C.UTF-8",
               # Mesa's shader cache lives in this grading's own folder (emptied for the
               # next submission), so the runs of one grading compile each shader once
               # (measured: a 32x32 chapter-10 run drops from 0.34 s to 0.12 s).
               "XDG_CACHE_HOME": str(cwd / ".cache"), "MESA_SHADER_CACHE_MAX_SIZE": "64M",
               "COURSE_GPU_TIMEOUT_SECONDS": str(GRADING_GPU_STEP_SECONDS)}
        for key in ("MESA_GL_VERSION_OVERRIDE", "LIBGL_ALWAYS_SOFTWARE", "GALLIUM_DRIVER",
                    "LP_NUM_THREADS"):
            if key in os.environ:
                env[key] = os.environ[key]
        return env

    def run(self, argv: list[str], cwd: Path, timeout: float | None = None,
            cpu_seconds: int | None = None) -> Run:
        """Runs argv in cwd inside the sandbox; returns only when every process of the
        run is gone."""
        timeout = timeout or self.limits.wall_seconds
        left = None if self.ends is None else self.ends - time.monotonic()
        if left is not None and left <= 0:
            return Run("total", "")
        out_of_total = left is not None and left < timeout
        timeout = min(timeout, left) if left is not None else timeout
        process = subprocess.Popen(self.command(argv, cpu_seconds or self.limits.cpu_seconds),
                                   cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, env=self.environment(cwd),
                                   start_new_session=True)
        kept, total, flooded = bytearray(), [0], threading.Event()
        output_limit = self.limits.output_mb << 20

        def drain():
            while chunk := os.read(process.stdout.fileno(), 1 << 16):
                total[0] += len(chunk)
                if len(kept) <= OUTPUT_KEPT * 4:
                    kept.extend(chunk[:OUTPUT_KEPT * 4 + 1 - len(kept)])
                if total[0] > output_limit and not flooded.is_set():
                    flooded.set()
                    self._stop(process)

        reader = threading.Thread(target=drain, daemon=True)
        reader.start()
        deadline, reason = time.monotonic() + timeout, None
        while True:
            try:
                code = process.wait(timeout=min(1.0, max(0.01, deadline - time.monotonic())))
                break
            except subprocess.TimeoutExpired:
                if time.monotonic() >= deadline:
                    reason = "time"
                elif self._folder_bytes(cwd) > self.limits.disk_mb << 20:
                    reason = "disk"
                if reason:
                    self._stop(process)
        self.kill_all(process)
        reader.join(timeout=30)
        process.stdout.close()
        if reader.is_alive():  # someone outside the sandbox holds the pipe: say so
            kept.extend(b"\n[the output pipe stayed open after every process was killed]")
        text = kept.decode("utf-8", "replace")
        if len(text) > OUTPUT_KEPT:
            text = text[:OUTPUT_KEPT] + "\n[output cut at 20 000 characters]"
        if flooded.is_set():
            return Run("output", text)
        if reason == "time":
            return Run("total" if out_of_total else None, text)
        if reason == "disk":
            return Run("disk", text)
        return Run(code, text)

    @staticmethod
    def _folder_bytes(folder: Path) -> int:
        total = 0
        for directory, _, files in os.walk(folder):
            for name in files:
                try:
                    total += os.lstat(os.path.join(directory, name)).st_blocks * 512
                except OSError:
                    pass
        return total

    def _stop(self, process: subprocess.Popen):
        try:
            os.kill(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.kill_all(process)

    def kill_all(self, process: subprocess.Popen | None = None):
        """Kills every process of the run: as root, every process of the sandbox's user
        (repeated until none is left); otherwise the run's process group."""
        if not self.root:
            if process is not None:
                try:
                    os.killpg(process.pid, signal.SIGKILL)
                except (ProcessLookupError, PermissionError):
                    pass
            return
        for attempt in range(500):
            alive = _live_processes(self.uid)
            if alive == [] or (alive is None and attempt == 3):  # without /proc: 3 times
                self._wait_for_the_dead_to_be_reaped()
                return
            subprocess.run([PYTHON, "-I", "-S", "-c", KILLER, str(self.uid), str(self.gid)],
                           stdin=subprocess.DEVNULL, capture_output=True)
            time.sleep(0.01)
        raise SandboxError(f"processes of {self.user} survive SIGKILL: "
                           f"{_live_processes(self.uid)}")

    def _wait_for_the_dead_to_be_reaped(self, most_seconds: float = 30.0):
        """A fork bomb's killed children are orphans that init reaps when it gets to
        them (seen slow on Debian 13 in a chroot); until then they count towards the
        user's process limit, and the next run could not even start its compiler."""
        deadline = time.monotonic() + most_seconds
        while time.monotonic() < deadline and _live_processes(self.uid, zombies=True):
            time.sleep(0.05)

    def _sweep_shared_temp(self):
        """Without private temporary folders, removes what the user left in the shared
        ones (so that nothing passes from one submission to the next)."""
        if not self.root or self.mount:
            return
        for folder in self.private_temp:
            subprocess.run(["find", folder, "-xdev", "-depth", "-user", str(self.uid),
                            "-delete"], capture_output=True)

    # ---------------------------------------------------------------- proof

    def check_access(self, unreadable: list[Path], unwritable: list[Path]) -> list[str]:
        """Asks, from inside the sandbox, which of these it can read or write; returns
        one line per path it should not reach but does."""
        script = ('for p; do case "$p" in r:*) [ -r "${p#r:}" ] && echo "readable: ${p#r:}";;'
                  ' w:*) [ -w "${p#w:}" ] && echo "writable: ${p#w:}";; esac; done; true')
        paths = [f"r:{p}" for p in unreadable if p.exists()] + \
                [f"w:{p}" for p in unwritable if p.exists()]
        run = self.run(["/bin/sh", "-c", script, "sh", *paths], self.scratch, timeout=30)
        problems = [line for line in run.output.splitlines()
                    if line.startswith(("readable: ", "writable: "))]
        if run.code != 0:
            problems.append(f"the access check itself failed ({run.code}): {run.output}")
        return problems

    def protections(self) -> list[str]:
        """What was in force, one line each, for the report."""
        lines = []
        if self.root:
            lines.append(f"ran as the unprivileged user {self.user} (uid {self.uid}), no "
                         "supplementary groups, no capabilities, no_new_privs")
        else:
            lines.append("ran as the grader's own user (the grader is not root): no user "
                         "separation, and only the namespaces below keep the instructor's "
                         "files out of reach; no capabilities, no_new_privs")
        names = [n[2:] for n in self.namespaces if n in ("--net", "--ipc", "--mount")]
        if names:
            line = "namespaces: " + ", ".join(names)
            if "net" in names:
                line += " (no network at all)"
            if self.mount:
                line += ("; private " + ", ".join(self.private_temp) +
                         (("; covered: " + ", ".join(self.hide)) if self.hide else ""))
            lines.append(line)
        else:
            lines.append("no namespaces (unshare is not allowed here): the network is "
                         "reachable; shared temporary folders are swept after each run")
        if self.closed:
            lines.append("closed to other users: " + ", ".join(map(str, self.closed)))
        lines.append("limits: " + self.limits.describe())
        if self.root:
            lines.append("every process of the user killed after each run, before its files "
                         "are read")
        else:
            lines.append("the run's process group killed after each run (a process that "
                         "starts a session of its own can outlive it)")
        return lines


class Direct(Sandbox):
    """Runs as the caller, with the limits and nothing else: for trusted code (the
    instructor's own starter, compiled by the course's tests) when no sandbox is active."""

    def __init__(self, limits: Limits | None = None):
        super().__init__(limits=limits)
        self.namespaces, self.mount, self.root, self.hide = [], False, False, []
        self.private_temp = []


def run_limited(command: list[str], cwd: Path, timeout: float | None = None,
                cpu_seconds: int | None = None) -> Run:
    """Runs command in the active sandbox, or directly with limits when there is none."""
    return (active() or Direct()).run(command, cwd, timeout, cpu_seconds)


def current_limits() -> Limits:
    box = active()
    return box.limits if box else Limits.from_environment()
