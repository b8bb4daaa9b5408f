"""What every ./course bench needs: the machine's name (CPU, cores, Mesa, LLVM, Mitsuba),
whether it was quiet while the bench ran, a median with its spread, and the one place
that writes a table into a book page (only when --update-book asks for it)."""

from __future__ import annotations

import json
import os
import platform
import re
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from course_tools.program_output import last_json_line

# Above this 1-minute load average per core, other work is taking CPU time from the
# bench and its figures say more about the neighbours than about the renderers.
START_SAMPLE_SECONDS = 2.0  # how long others' use is measured before a bench
QUIET_LOAD_PER_CORE = 0.3


# ---------------------------------------------------------------- the machine

def cpu_model() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown"


# The widest vector extension first: what decides how many lanes a CPU renderer (Mesa's
# llvmpipe, Mitsuba's LLVM backend) can run at once, so every figure names it.
VECTOR_EXTENSIONS = (("avx512f", "AVX-512"), ("avx2", "AVX2"), ("avx", "AVX"),
                     ("sse4_2", "SSE4.2"), ("neon", "NEON"), ("asimd", "NEON"))


def vector_extension(cpuinfo: str | None = None) -> str:
    """The CPU's widest vector extension ('AVX-512', 'AVX2', ...), from /proc/cpuinfo's
    flags; 'unknown' where there are none to read."""
    if cpuinfo is None:
        try:
            cpuinfo = Path("/proc/cpuinfo").read_text()
        except OSError:
            return "unknown"
    flags = set()
    for line in cpuinfo.splitlines():
        if line.startswith(("flags", "Features")):
            flags.update(line.split(":", 1)[1].split())
    return next((name for flag, name in VECTOR_EXTENSIONS if flag in flags), "unknown")


def mesa_version(gl_version: str) -> str | None:
    """'4.5 (Core Profile) Mesa 22.3.6' -> '22.3.6'; None for a GL that is not Mesa."""
    match = re.search(r"Mesa (\S+)", gl_version)
    return match.group(1) if match else None


def llvm_version(gl_renderer: str) -> str | None:
    """'llvmpipe (LLVM 15.0.6, 256 bits)' -> '15.0.6'; None for a GPU's renderer."""
    match = re.search(r"LLVM ([\w.]+)", gl_renderer)
    return match.group(1) if match else None


def mitsuba_version() -> str | None:
    try:
        import mitsuba
    except ImportError:
        return None
    return mitsuba.__version__


def llvmpipe_lanes(gl_renderer: str) -> int | None:
    """'llvmpipe (LLVM 15.0.6, 256 bits)' -> 8: the float32 lanes llvmpipe runs side by
    side (LP_NATIVE_VECTOR_WIDTH); None for a GPU's renderer."""
    match = re.search(r"llvmpipe .*?(\d+) bits", gl_renderer)
    return int(match.group(1)) // 32 if match else None


def mitsuba_lanes(vectors: str) -> int:
    """The lanes of Mitsuba's LLVM backend: Dr.Jit's core chooses its vector width from
    the CPU's features, 16 float32 lanes with AVX-512 (its VL part, which every AVX-512
    CPU since Skylake has), 8 with AVX or AVX2, 4 with SSE4.2 (or NEON)."""
    return 16 if vectors == "AVX-512" else 8 if vectors in ("AVX2", "AVX") else 4


def mitsuba_embree() -> bool | None:
    """Whether this Mitsuba traces rays through Embree (its CPU variants' ray tracer)."""
    try:
        import mitsuba
    except ImportError:
        return None
    return bool(getattr(mitsuba, "MI_ENABLE_EMBREE", False))


def describe_machine(program_stats: dict) -> dict:
    """The machine, from /proc and from a chapter program's --json line (its GL strings)."""
    renderer, gl_version = program_stats["renderer"], program_stats["gl_version"]
    vectors = vector_extension()
    return {"cpu": cpu_model(), "cores": os.cpu_count(), "vectors": vectors,
            "gl_renderer": renderer,
            "gl_version": gl_version, "mesa": mesa_version(gl_version),
            "llvm": llvm_version(renderer), "llvmpipe_lanes": llvmpipe_lanes(renderer),
            "mitsuba": mitsuba_version(), "mitsuba_lanes": mitsuba_lanes(vectors),
            "mitsuba_embree": mitsuba_embree(), "python": platform.python_version()}


def machine_words(machine: dict) -> str:
    """'AMD EPYC (2 cores, AVX2), Mesa 22.3.6 with LLVM 15.0.6 (`llvmpipe (...)`), 8
    lanes; Mitsuba's LLVM backend 8 lanes, with Embree': what decides the ratios. A
    report from before these were recorded leaves them out."""
    vectors = f", {machine['vectors']}" if machine.get("vectors") else ""
    words = f"{machine['cpu']} ({machine['cores']} cores{vectors}), "
    if machine.get("mesa"):
        words += f"Mesa {machine['mesa']}"
        words += f" with LLVM {machine['llvm']}" if machine.get("llvm") else ""
    else:
        words += f"OpenGL {machine['gl_version']}"
    words += f" (`{machine['gl_renderer']}`)"
    if machine.get("llvmpipe_lanes"):
        words += f", {machine['llvmpipe_lanes']} lanes"
    if machine.get("mitsuba") and machine.get("mitsuba_lanes"):
        embree = {True: ", with Embree", False: ", without Embree"}.get(
            machine.get("mitsuba_embree"), "")
        words += f"; Mitsuba's LLVM backend {machine['mitsuba_lanes']} lanes{embree}"
    return words


def program_stats(command: list, bench: str, env: dict | None = None) -> dict:
    """One run of a chapter's program: its --json statistics (its last JSON line). A run
    that fails stops the bench with the program's own message."""
    command = [str(word) for word in command]
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    if result.returncode != 0:
        raise SystemExit(f"bench {bench}: {' '.join(command)} failed "
                         f"({result.returncode}):\n{result.stderr}")
    return last_json_line(result.stdout, " ".join(command))


def today() -> str:
    return time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())


# ---------------------------------------------------------------- was it quiet?

def busy_cpu_seconds() -> float | None:
    """CPU time all processes have spent busy since boot (/proc/stat), or None."""
    try:
        fields = Path("/proc/stat").read_text().splitlines()[0].split()[1:]
    except OSError:
        return None
    user, nice, system, idle, iowait, irq, softirq, steal = map(int, fields[:8])
    return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")


def own_cpu_seconds() -> float:
    """CPU time of this process and its finished children (the renderers it ran)."""
    return sum(usage.ru_utime + usage.ru_stime for usage in
               (resource.getrusage(resource.RUSAGE_SELF),
                resource.getrusage(resource.RUSAGE_CHILDREN)))


class QuietWatch:
    """Watches how busy the machine is around a bench: the 1-minute load average at the
    start and the end, and the CPU time other processes took in between (the load at
    the end counts the bench's own renders, so it alone cannot say whether others ran)."""

    def __init__(self):
        self.cores = os.cpu_count() or 1
        self.load_start = os.getloadavg()[0]
        # The load average lags a minute behind: it still counts work that has just
        # finished (the previous bench of the same ./course bench, a build). What runs
        # now is what others take of the CPU over a moment before the bench begins.
        self.others_at_start = others_cores_over(START_SAMPLE_SECONDS)
        self.wall_start = time.monotonic()
        self.busy_start = busy_cpu_seconds()
        self.own_start = own_cpu_seconds()
        warn_if_busy(self.report_so_far())

    def report_so_far(self) -> dict:
        return {"cores": self.cores, "load_start": self.load_start,
                "others_at_start": self.others_at_start,
                "threshold": QUIET_LOAD_PER_CORE * self.cores,
                "quiet": is_quiet(self.load_start, None, self.cores, self.others_at_start)}

    def finish(self) -> dict:
        wall = time.monotonic() - self.wall_start
        busy = busy_cpu_seconds()
        others = None
        if busy is not None and self.busy_start is not None and wall > 0:
            others = others_cores(busy - self.busy_start, own_cpu_seconds() - self.own_start,
                                  wall)
        report = {**self.report_so_far(), "load_end": os.getloadavg()[0],
                  "other_processes_cores": others,
                  "quiet": is_quiet(self.load_start, others, self.cores,
                                    self.others_at_start)}
        warn_if_busy(report)
        return report


def is_quiet(load_start: float, other_processes_cores: float | None, cores: int,
             others_at_start: float | None = None) -> bool:
    """Quiet: at the start, and other processes' use of the CPU during the bench (in
    cores), both at most QUIET_LOAD_PER_CORE per core. The start is judged by others'
    use measured just before it where /proc/stat gives it, else by the load average."""
    limit = QUIET_LOAD_PER_CORE * cores
    start = load_start if others_at_start is None else others_at_start
    return start <= limit and (other_processes_cores or 0.0) <= limit


def others_cores_over(seconds: float) -> float | None:
    """Cores' worth of CPU that other processes used over the next `seconds`, or None
    where /proc/stat does not say."""
    busy, own = busy_cpu_seconds(), own_cpu_seconds()
    if busy is None:
        return None
    time.sleep(seconds)
    return others_cores(busy_cpu_seconds() - busy, own_cpu_seconds() - own, seconds)


def others_cores(busy_seconds: float, own_seconds: float, wall: float) -> float:
    """Cores' worth of CPU, on average over `wall` seconds, that processes other than
    this one and its finished children used: all busy time less our own."""
    return max(busy_seconds - own_seconds, 0.0) / wall


def quiet_words(quiet: dict) -> str:
    """One sentence for the report: the loads, and whether the figures can be trusted."""
    words = f"1-minute load average {quiet['load_start']:.2f} at the start"
    if quiet.get("others_at_start") is not None:
        words += (f" (other processes using {quiet['others_at_start']:.2f} cores "
                  "just before)")
    if "load_end" in quiet:
        words += f", {quiet['load_end']:.2f} at the end (the bench's own renders included)"
    if quiet.get("other_processes_cores") is not None:
        words += (f"; other processes used {quiet['other_processes_cores']:.2f} cores on "
                  "average while it ran")
    if quiet["quiet"]:
        return f"The machine was quiet: {words}."
    return (f"**The machine was NOT quiet** ({words}; more than "
            f"{QUIET_LOAD_PER_CORE} per core): other work skewed these figures.")


def warn_if_busy(quiet: dict):
    if quiet["quiet"]:
        return
    bar = "!" * 78
    print(f"{bar}\nbench: WARNING: this machine is busy. {quiet_words(quiet)}\n"
          f"bench: the figures below are not fit for the book.\n{bar}",
          file=sys.stderr, flush=True)


# ---------------------------------------------------------------- medians and spreads

def summarise(values: list[float]) -> dict:
    """The median of repeated measurements, their range, and the range relative to the
    median (0.1: the runs lay within 10% of the median's size of each other)."""
    median = statistics.median(values)
    low, high = min(values), max(values)
    return {"median": median, "min": low, "max": high,
            "spread": (high - low) / median if median else 0.0, "runs": list(values)}


def spread_words(summary: dict, digits: int = 0) -> str:
    """'72,100–80,300 (11%)'."""
    return (f"{summary['min']:,.{digits}f}–{summary['max']:,.{digits}f} "
            f"({100 * summary['spread']:.0f}%)")


# ---------------------------------------------------------------- the book's pages

def write_table(page: Path, start: str, end: str, table: str) -> bool:
    """Replaces what lies between the page's start and end markers with the table.
    False (and nothing written) when the page lacks the markers."""
    text = page.read_text()
    if start not in text or end not in text:
        print(f"bench: {page} has no {start} ... {end}: table not written", file=sys.stderr)
        return False
    head, rest = text.split(start, 1)
    _, tail = rest.split(end, 1)
    page.write_text(f"{head}{start}\n{table}\n{end}{tail}")
    return True


# Machines differ (an AMD with AVX2, an Intel with AVX-512), so a page keeps one table
# per kind of CPU measured: between a bench's markers, each kind's table follows a line
# naming it, and a bench replaces only the table of the kind it ran on.
KIND_LINE = re.compile(r"^<!-- measured on: (.+?) -->$", re.MULTILINE)


def machine_kind(machine: dict) -> str:
    """'Intel(R) Xeon(R) Processor, AVX-512': the CPU and its widest vector extension."""
    vectors = machine.get("vectors") or "unknown vector extension"
    return f"{machine.get('cpu') or 'unknown CPU'}, {vectors}"


def tables_by_kind(block: str) -> list[tuple[str | None, str]]:
    """(kind, table) for each table between a bench's markers; kind None for a table
    written before tables were kept per kind."""
    parts = KIND_LINE.split(block)
    tables = [(None, parts[0].strip())] if parts[0].strip() else []
    tables += [(kind, text.strip()) for kind, text in zip(parts[1::2], parts[2::2])]
    return tables


def is_measurement(text: str) -> bool:
    """Every bench's table says when and where it was "Measured"."""
    return "Measured" in text


def write_machine_table(page: Path, start: str, end: str, table: str,
                        machine: dict) -> bool:
    """write_table for the table of one kind of CPU: the other kinds' tables stay. An
    older table without a kind is replaced when it names this machine's CPU, and kept
    (as the record of another machine) when it does not; words that are no measurement
    (the page's "no quiet run recorded yet") go once a table comes."""
    text = page.read_text()
    if start not in text or end not in text:
        print(f"bench: {page} has no {start} ... {end}: table not written", file=sys.stderr)
        return False
    kind, cpu = machine_kind(machine), machine.get("cpu") or ""
    block = text.split(start, 1)[1].split(end, 1)[0]
    kept = [(k, t) for k, t in tables_by_kind(block)
            if k != kind and not (k is None and ((cpu and cpu in t) or not is_measurement(t)))]
    body = "\n\n".join((f"<!-- measured on: {k} -->\n{t}" if k else t)
                         for k, t in [*kept, (kind, table.strip())])
    return write_table(page, start, end, body)


def book_or_not(update_book: bool, page: Path, start: str, end: str, table: str,
                machine: dict | None = None):
    """Writes the table into the page when asked (--update-book); says so either way.
    With the machine it ran on, the table is that kind of CPU's (write_machine_table)."""
    if not update_book:
        print(f"bench: {page.name} left as it is (./course bench --update-book writes "
              "this table there)")
        return
    written = (write_machine_table(page, start, end, table, machine) if machine
               else write_table(page, start, end, table))
    if written:
        print(f"bench: wrote the table into {page}")


def publish(report: dict, out: Path, table: str, update_book: bool, page: Path, start: str,
            end: str):
    """The end of a bench: every run in `out` (JSON), the table printed, and written into
    the page only when asked (book_or_not)."""
    publish_pages(report, out, {page: table}, {page: (page, start, end)}, update_book)


def publish_pages(report: dict, out: Path, tables: dict, pages: dict, update_book: bool):
    """publish() for a bench whose tables go to several pages: pages maps a name to
    (page, start marker, end marker), tables the same name to its table. The report is
    written once."""
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2) + "\n")
    for name in pages:
        print(tables[name])
    print(f"bench: wrote {out}")
    for name, (page, start, end) in pages.items():
        book_or_not(update_book, page, start, end, tables[name], report.get("machine"))
