"""Where the step loop spends its time: ``perf`` samples attributed to numba's machine code.

    python tools/bench/profile_jit.py [--n 50] [--seconds 5] [--settled] [--top 12] [--asm 2]
    python tools/bench/profile_jit.py --bed shaken_visco_512   # a bed of count_instructions.py

numba's code lives in anonymous memory that ``perf report`` cannot name. This script runs the
benchmark scene (``bench_solver.scene_model``) in-process, attaches ``perf record`` to itself
while the loop runs, copies every executable anonymous mapping out of ``/proc/self/maps``, and
then attributes the samples: per mapping (named by the compiled functions whose entry points it
holds), per 128-byte block, and -- for the ``--asm`` hottest blocks -- per instruction, with
``objdump`` disassembly. Needs ``perf`` and ``objdump`` (binutils); reading your own process
may need ``kernel.perf_event_paranoid`` <= 1 outside a container.

What it found so far (see git log): atomic reference counting in the loop (fixed with
``x3dpd._jit.loop_kernel``), stack spills in the filter passes (pair filter moved to its own
function), negative-index wrap-around code (unsigned indices), divisions in the friction law.
"""

from __future__ import annotations

import argparse
import collections
import ctypes
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_solver import scene_model  # noqa: E402
from count_instructions import BEDS  # noqa: E402

from x3dpd.solver.simulation import Simulation  # noqa: E402


def _entry_points() -> dict[int, str]:
    out = {}
    for modname, mod in list(sys.modules.items()):
        if not modname.startswith("x3dpd"):
            continue
        for name in dir(mod):
            obj = getattr(mod, name)
            if isinstance(obj, numba.core.registry.CPUDispatcher):
                for cres in obj.overloads.values():
                    try:
                        addr = cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name)
                    except Exception:  # noqa: BLE001 (not every overload exposes a pointer)
                        continue
                    out[addr] = name
    return out


def _code_mappings(folder: Path) -> dict[int, Path]:
    maps = {}
    for line in Path("/proc/self/maps").read_text().splitlines():
        parts = line.split()
        lo, hi = (int(v, 16) for v in parts[0].split("-"))
        if "x" in parts[1] and len(parts) < 6 and hi - lo < 64 << 20:  # anonymous, executable
            path = folder / f"{lo:x}.bin"
            path.write_bytes(ctypes.string_at(lo, hi - lo))
            maps[lo] = path
    return maps


def _disassemble(base: int, path: Path, start: int, stop: int) -> list[str]:
    return subprocess.run(
        [
            "objdump",
            "-D",
            "-b",
            "binary",
            "-m",
            "i386:x86-64",
            f"--adjust-vma={base:#x}",
            f"--start-address={start:#x}",
            f"--stop-address={stop:#x}",
            str(path),
        ],
        capture_output=True,
        text=True,
        check=False,
    ).stdout.splitlines()


#: blocks this close (bytes) join one region of _print_regions
GAP = int(os.environ.get("PROFILE_GAP", "512"))


def _print_regions(blocks, per_ip, maps, bases, sizes, names, total, top) -> None:
    """Runs of hot 128-byte blocks (gaps under 512 bytes joined): their share of the samples,
    the function whose entry precedes them, and a signature of their instructions -- packed
    (zmm/ymm) and scalar floating point, square roots and divisions -- to tell the loops apart
    (the vectorized responses, the scatter passes, the integration)."""
    hot = sorted(b for b, c in blocks.items() if c >= 0.002 * total)
    runs = []
    for b in hot:
        if runs and b - runs[-1][1] < GAP:
            runs[-1][1] = b
        else:
            runs.append([b, b])
    rows = []
    for lo, hi in runs:
        share = sum(c for b, c in blocks.items() if lo <= b <= hi)
        base = next(m for m in bases if m <= lo < m + sizes[m])
        entry = max((a for a in names if base <= a <= lo), default=None)
        sig = collections.Counter()
        for line in _disassemble(base, maps[base], lo, hi + 128):
            fields = line.split("\t")[-1].split() if "\t" in line else []
            op = fields[0] if fields else ""
            if "zmm" in line or "ymm" in line:
                sig["packed"] += 1
            elif op.endswith("sd"):
                sig["scalar"] += 1
            if "sqrt" in op:
                sig["sqrt"] += 1
            if op.startswith("vdiv") or op.startswith("div"):
                sig["div"] += 1
        rows.append((share, lo, hi, names.get(entry, "?"), sig))
    print(f"\nhottest {top} regions:")
    for share, lo, hi, name, sig in sorted(rows, reverse=True)[:top]:
        print(
            f"  {100 * share / total:5.1f} %  {lo:#x}..{hi + 128:#x} after {name}: "
            + ", ".join(f"{k} {v}" for k, v in sorted(sig.items()))
        )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=50)
    ap.add_argument("--seconds", type=float, default=5.0)
    ap.add_argument("--settled", action="store_true", help="profile a settled bed (no drive)")
    ap.add_argument(
        "--bed",
        help="a bed prepared by count_instructions.py --prepare (restored, not settled again): "
        f"{', '.join(sorted(BEDS))}, mip_N or a shipped deck's name (beam_64)",
    )
    ap.add_argument("--top", type=int, default=12, help="hottest 128-byte blocks to list")
    ap.add_argument("--asm", type=int, default=2, help="hottest blocks to disassemble")
    ap.add_argument(
        "--regions",
        type=int,
        default=0,
        help="list the hottest N regions (runs of hot blocks) with what their code does",
    )
    args = ap.parse_args(argv)
    deck = Path(__file__).resolve().parents[2] / "decks" / f"{args.bed}.inp"
    if args.bed and args.bed not in BEDS and not re.fullmatch(r"mip_\d+", args.bed):
        if not deck.is_file():
            ap.error(f"--bed {args.bed}: not a bed of count_instructions.py, mip_N or a deck")
    for tool in ("perf", "objdump"):
        if shutil.which(tool) is None:
            print(f"{tool} not found; install linux-tools / binutils", file=sys.stderr)
            return 2

    if args.bed and deck.is_file():  # a shipped deck, 4000 steps in (as count_instructions.py)
        from x3dpd import build, load_deck

        sim = Simulation(build(load_deck(deck)), itrac=10**9)
        sim.initialize()
        sim.advance(4000, max_rows=1)
    elif args.bed:
        from count_instructions import bed_simulation

        sim = bed_simulation(args.bed)
        sim.advance(2000, max_rows=1)
    else:
        sim = Simulation(scene_model(args.n, drive=not args.settled)[0], itrac=10**9)
        sim.initialize()
        sim.advance(300_000 if args.settled else 2000, max_rows=1)  # compile, settle/warm
    t = time.perf_counter()
    sim.advance(20_000, max_rows=1)
    per_step = (time.perf_counter() - t) / 20_000
    steps = max(int(args.seconds / per_step), 1)

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        data = tmp / "perf.data"
        rec = subprocess.Popen(
            ["perf", "record", "-q", "-e", "cpu-clock", "-p", str(os.getpid()), "-o", str(data)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        time.sleep(0.5)
        t = time.perf_counter()
        sim.advance(steps, max_rows=1)
        elapsed = time.perf_counter() - t
        rec.send_signal(subprocess.signal.SIGINT)
        rec.wait()
        maps = _code_mappings(tmp)
        names = _entry_points()
        script = subprocess.run(
            ["perf", "script", "-i", str(data), "-F", "ip"],
            capture_output=True,
            text=True,
            check=False,
        )
        ips = [int(v, 16) for v in script.stdout.split() if re.fullmatch(r"[0-9a-f]+", v)]
        print(
            f"{args.bed or f'n={args.n}'}{' settled' if args.settled else ''}: {steps} steps, "
            f"{elapsed / steps * 1e6:.3f} us/step under perf; {len(ips)} samples"
        )

        bases = sorted(maps)
        sizes = {b: maps[b].stat().st_size for b in bases}
        per_map = collections.Counter()
        blocks = collections.Counter()
        per_ip = collections.Counter(ips)
        for ip in ips:
            for b in bases:
                if b <= ip < b + sizes[b]:
                    per_map[b] += 1
                    blocks[ip >> 7 << 7] += 1
                    break
            else:
                per_map["other"] += 1
        print("\nsamples per code mapping:")
        for b, c in per_map.most_common():
            inside = sorted({v for a, v in names.items() if b != "other" and b <= a < b + sizes[b]})
            label = "outside numba's code" if b == "other" else f"{b:#x} {', '.join(inside)}"
            print(f"  {100 * c / len(ips):5.1f} %  {label}")
        print(f"\nhottest {args.top} blocks of 128 bytes:")
        for blk, c in blocks.most_common(args.top):
            print(f"  {100 * c / len(ips):5.1f} %  {blk:#x}")
        if args.regions:
            _print_regions(blocks, per_ip, maps, bases, sizes, names, len(ips), args.regions)
        for blk, _ in blocks.most_common(args.asm):
            base = next(b for b in bases if b <= blk < b + sizes[b])
            start = max(blk - 48, base)
            asm = _disassemble(base, maps[base], start, blk + 128)
            print(f"\n{blk:#x} (samples per instruction; a stall shows on the next one):")
            for line in asm:
                m = re.match(r"\s*([0-9a-f]+):", line)
                if m and int(m.group(1), 16) >= blk:  # decoding began early, in sync by now
                    print(f"  {per_ip.get(int(m.group(1), 16), 0):6d} {line.strip()[:110]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
