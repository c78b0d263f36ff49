#!/usr/bin/env python3
"""Where the time of a benchmark goes inside the machine code llvmpipe compiled for it (lavapipe only).

Lavapipe compiles every shader to x86 code at run time, so a CPU profiler sees only anonymous addresses.
This tool runs `smokesvd bench FILTER` (or, with --run, any smokesvd command) in the background, samples
it with `perf record -e cpu-clock` (a software clock: no hardware counters needed), disassembles the
process's anonymous executable mappings (the compiled shaders) with gdb while it still runs, and prints,
per compiled function, its share of the samples and its instruction mix: calls (llvmpipe compiles each
texel fetch as a call to a fetch function), multiplies and adds (llvmpipe emits no fused multiply-add for
the shaders' arithmetic), blends with the execution mask, vector moves (spills and reloads); and the share
of the small leaf functions (under 100 instructions, no calls: llvmpipe's texel-fetch helpers). `--top N`
also lists the N hottest instructions. `--save DIR` keeps the disassembly (jit.asm) and the sampled
addresses (samples.txt, one hexadecimal address a line); `--from DIR` reports on such a folder again
without running anything.

    tools/jit_profile.py conv/3d-3x3x3-32 --seconds 10
    tools/jit_profile.py conv-net/grho-small --top 20 --save /tmp/conv-profile
    tools/jit_profile.py --from /tmp/conv-profile --top 40
    tools/jit_profile.py --run "train grho-coarse --data data/small --out /tmp/run --steps 300 --overwrite" --settle 60

A benchmark repeats its first kernel `--runs` times before the next, so the samples are of that kernel;
the training-step benchmarks time a fixed five steps and end too soon: profile a training run with --run.

Needs perf (Debian: linux-perf) and gdb, and permission to attach to the process (root, or
kernel.yama.ptrace_scope = 0 and kernel.perf_event_paranoid <= 2). docs/benchmarks.md, "Findings about
lavapipe", shows what it found in the convolution kernel.
"""
import argparse
import collections
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

INSTRUCTION = re.compile(r"\s*(?:=>)?\s*0x([0-9a-f]+)(?: <[^>]*>)?:\s*(.*)")
PADDING = ("add    %al,(%rax)", "data16", "nop", "cs nopw", "int3")
# Mnemonics per kind; a trailing * matches any ending (vfmadd231ps, vfmadd213ps, ...).
COUNTED = {
    "calls": ("call",),
    "multiplies": ("vmulps",),
    "adds": ("vaddps", "vsubps"),
    "fused multiply-adds": ("vfmadd*", "vfmsub*", "vfnmadd*"),
    "blends": ("vblendvps", "vpblendvb", "vpblendmd"),
    "vector moves": ("vmovaps", "vmovups", "vmovdqa", "vmovdqu", "vmovdqa32", "vmovdqu32"),
    "lane extracts": ("vpextrd", "vextracti128", "vextractf128", "vmovd"),
}


def is_kind(mnemonic, names):
    return any(mnemonic == n or (n.endswith("*") and mnemonic.startswith(n[:-1])) for n in names)


def require(tool):
    if shutil.which(tool) is None:
        sys.exit(f"jit_profile: '{tool}' is not installed (Debian: apt-get install {'linux-perf' if tool == 'perf' else tool})")


def executable_anonymous_mappings(pid):
    """(start, end) of every executable mapping with no file behind it: the compiled shaders."""
    ranges = []
    with open(f"/proc/{pid}/maps") as maps:
        for line in maps:
            fields = line.split()
            if len(fields) == 5 and "x" in fields[1]:
                start, end = (int(v, 16) for v in fields[0].split("-"))
                ranges.append((start, end))
    return ranges


def disassemble(pid, ranges, path):
    """Writes gdb's disassembly of the ranges to path. Each range is disassembled on its own, and one that gdb
    cannot read is skipped: in a gdb command file the first error ends the file, which would drop every
    mapping after it."""
    listing = ", ".join(f"({start:#x}, {end:#x})" for start, end in ranges)
    commands = ["set pagination off", f"set logging file {path}", "set logging overwrite on",
                "set logging redirect on", "set logging enabled on",
                "python",
                f"for start, end in [{listing}]:",
                "    try:",
                "        gdb.execute(f'disassemble {start:#x},{end:#x}')",
                "    except gdb.error:",
                "        pass",
                "end",
                "set logging enabled off", "detach", "quit"]
    script = path + ".gdb"
    with open(script, "w") as f:
        f.write("\n".join(commands) + "\n")
    subprocess.run(["gdb", "-p", str(pid), "-batch", "-x", script], stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=False)
    os.remove(script)
    with open(path) as f:
        lines = f.readlines()
    seen = set()
    with open(path, "w") as f:
        for line in lines:
            m = INSTRUCTION.match(line)
            if not m:
                continue
            address = int(m.group(1), 16)
            if address not in seen and any(start <= address < end for start, end in ranges):
                seen.add(address)
                f.write(line)


def read_disassembly(path):
    """[(address, instruction text)] of a gdb disassembly, in address order, each address once."""
    code = {}
    with open(path) as f:
        for line in f:
            m = INSTRUCTION.match(line)
            if m:
                code.setdefault(int(m.group(1), 16), m.group(2).strip())
    return sorted(code.items())


def read_samples(path):
    with open(path) as f:
        return collections.Counter(int(v, 16) for v in f.read().split())


def functions(code):
    """Splits the disassembly at each `ret`, dropping padding (zero bytes read as `add %al,(%rax)`, nops)."""
    found, current = [], []
    for address, text in code:
        if text.startswith(PADDING):
            continue
        current.append((address, text))
        if text.startswith("ret"):
            found.append(current)
            current = []
    if current:
        found.append(current)
    return found


def write_sampled_addresses(perf_data, path):
    out = subprocess.run(["perf", "script", "-i", perf_data, "-F", "ip"], capture_output=True, text=True,
                         check=True).stdout
    with open(path, "w") as f:
        f.write(out)


def report(code, samples, top, out):
    total = sum(samples.values())
    if total == 0:
        sys.exit("jit_profile: perf recorded no samples (is the benchmark still running?)")
    in_code = 0
    out.write(f"{total} samples; per compiled function (share of all samples, instructions, mix):\n")
    rows = []
    for body in functions(code):
        share = sum(samples.get(a, 0) for a, _ in body)
        in_code += share
        mnemonics = collections.Counter(text.split()[0] for _, text in body if text)
        mix = {kind: sum(n for m, n in mnemonics.items() if is_kind(m, names)) for kind, names in COUNTED.items()}
        rows.append((share, body[0][0], len(body), mix))
    leaves = sum(share for share, _, length, mix in rows if length < 100 and mix["calls"] == 0)
    for share, start, length, mix in sorted(rows, reverse=True):
        if share < 0.005 * total:
            continue
        described = ", ".join(f"{name} {n}" for name, n in mix.items() if n)
        out.write(f"  {100 * share / total:5.1f} %  {start:#x}  {length:5d} instructions: {described}\n")
    out.write(f"  {100 * (total - in_code) / total:5.1f} %  outside compiled shaders (driver, kernel, program)\n")
    out.write(f"small leaf functions (under 100 instructions, no calls: the fetch helpers): {100 * leaves / total:.1f} %\n")
    if top:
        out.write(f"the {top} hottest instructions:\n")
        text_at = dict(code)
        for address, n in samples.most_common():
            if address in text_at:
                out.write(f"  {100 * n / total:5.2f} %  {address:#x}  {text_at[address]}\n")
                top -= 1
                if top == 0:
                    break


def profile(args, folder):
    """Runs the benchmark (or the --run command), samples it, and writes jit.asm and samples.txt into folder."""
    for tool in ("perf", "gdb"):
        require(tool)
    if not os.access(args.smokesvd, os.X_OK):
        sys.exit(f"jit_profile: {args.smokesvd}: not an executable program (build it, or pass --smokesvd)")
    command = shlex.split(args.run) if args.run else ["bench", args.filter, "--no-reference", "--runs", "100000"]
    log_path = os.path.join(folder, "program.log")
    with open(log_path, "w") as log:
        bench = subprocess.Popen([args.smokesvd] + command, stdout=subprocess.DEVNULL, stderr=log)
    try:
        time.sleep(args.settle)
        if bench.poll() is not None:
            with open(log_path) as log:
                said = log.read().strip().splitlines()
            if bench.returncode != 0:
                sys.exit(f"jit_profile: 'smokesvd {shlex.join(command)}' failed: {said[-1] if said else 'no message'}")
            sys.exit(f"jit_profile: 'smokesvd {shlex.join(command)}' ended within the {args.settle:g} s of --settle, "
                     f"before sampling (the training-step benchmarks time a fixed five steps: profile a kernel "
                     f"benchmark, which runs --runs times, or a training run with --run)")
        perf_data = os.path.join(folder, "perf.data")
        subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", "2000", "-p", str(bench.pid),
                        "-o", perf_data, "--", "sleep", str(args.seconds)], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        disassemble(bench.pid, executable_anonymous_mappings(bench.pid), os.path.join(folder, "jit.asm"))
    finally:
        bench.send_signal(signal.SIGTERM)
        bench.wait()
    write_sampled_addresses(perf_data, os.path.join(folder, "samples.txt"))
    os.remove(perf_data)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("filter", nargs="?", help="the benchmark to profile, as `smokesvd bench FILTER` takes it")
    parser.add_argument("--smokesvd", default="build/smokesvd", help="the program (default: build/smokesvd)")
    parser.add_argument("--settle", type=float, default=10, help="seconds to wait before sampling: compilation and warm-up")
    parser.add_argument("--seconds", type=float, default=10, help="seconds to sample")
    parser.add_argument("--top", type=int, default=0, help="also list the N hottest instructions")
    parser.add_argument("--save", help="keep the disassembly and the samples in this folder")
    parser.add_argument("--from", dest="saved", help="report on a folder written by --save; runs nothing")
    parser.add_argument("--run", help="profile this smokesvd command (its arguments, in quotes) instead of a benchmark")
    args = parser.parse_args()
    if args.saved:
        folder = args.saved
        for name in ("jit.asm", "samples.txt"):
            if not os.path.isfile(os.path.join(folder, name)):
                sys.exit(f"jit_profile: {folder}: no {name} (a folder written by --save holds jit.asm and samples.txt)")
        report(read_disassembly(os.path.join(folder, "jit.asm")), read_samples(os.path.join(folder, "samples.txt")),
               args.top, sys.stdout)
        return
    if not args.filter and not args.run:
        parser.error("name the benchmark to profile, a command with --run, or --from a saved folder")
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.save or scratch
        os.makedirs(folder, exist_ok=True)
        profile(args, folder)
        report(read_disassembly(os.path.join(folder, "jit.asm")), read_samples(os.path.join(folder, "samples.txt")),
               args.top, sys.stdout)


if __name__ == "__main__":
    main()
