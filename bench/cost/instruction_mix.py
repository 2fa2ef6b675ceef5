#!/usr/bin/env python3
"""Instruction mix of a particle-step, from a callgrind profile with per-instruction counts.

  valgrind --tool=callgrind --dump-instr=yes --dump-line=no --toggle-collect=adem_world_step \
      --callgrind-out-file=OUT BINARY ...
  instruction_mix.py OUT BINARY PARTICLE_STEPS

Counts, per particle-step, the executed instructions of BINARY (self cost, calls excluded) by
kind: floating-point operations (scalar = 1, packed double = 2), of which divisions and square
roots; memory operands (loads and stores, with their bytes); the rest. Reads the disassembly with
objdump. docs/performance.md ("Cost model") uses it."""
import re
import subprocess
import sys

def executed_counts(path, binary, other=None):
    counts = {}
    in_obj = False
    skip_next = False
    addr = 0
    cur_ob = None
    obnames = {}
    for line in open(path):
        line = line.rstrip("\n")
        m = re.match(r"^(c?ob)=\((\d+)\)(?: (.*))?$", line)
        if m:
            kind, num, name = m.groups()
            if name:
                obnames[num] = name
            if kind == "ob":
                cur_ob = obnames.get(num)
                in_obj = cur_ob is not None and cur_ob.endswith(binary.split("/")[-1])
            continue
        if line.startswith("calls="):
            skip_next = True
            continue
        m = re.match(r"^(0x[0-9a-f]+|[+-]\d+|\*)\s+(\d+)", line)
        if not m:
            continue
        pos, cost = m.groups()
        if pos.startswith("0x"):
            addr = int(pos, 16)
        elif pos != "*":
            addr += int(pos)
        if skip_next:
            skip_next = False
            continue
        if in_obj:
            counts[addr] = counts.get(addr, 0) + int(cost)
        elif other is not None and cur_ob:
            lib = cur_ob.split("/")[-1]
            other[lib] = other.get(lib, 0) + int(cost)
    return counts

def disassembly(binary):
    out = subprocess.run(["objdump", "-d", "--no-show-raw-insn", binary], capture_output=True,
                         text=True, check=True).stdout
    ins = {}
    for line in out.splitlines():
        m = re.match(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*)$", line)
        if m:
            ins[int(m.group(1), 16)] = (m.group(2), m.group(3))
    return ins

SCALAR = {"addsd", "subsd", "mulsd", "divsd", "sqrtsd", "minsd", "maxsd"}
PACKED = {"addpd", "subpd", "mulpd", "divpd", "sqrtpd", "minpd", "maxpd"}

def operand_bytes(mn, ops):
    if mn.endswith("pd") or mn.endswith("ps") or mn in ("movups", "movaps", "movdqu", "movdqa") \
       or "xmmword" in ops:
        return 16
    if mn.endswith("sd") or mn in ("movq",):
        return 8
    if re.search(r"%r[a-z0-9]+\b", ops) and not re.search(r"%e|%[a-d]l|%[sd]il", ops):
        return 8
    if re.search(r"%e[a-z]+|%r\d+d", ops):
        return 4
    if re.search(r"%[a-d]l|%r\d+b|%[sd]il", ops) or mn.endswith("b"):
        return 1
    return 8

def main():
    path, binary, steps = sys.argv[1], sys.argv[2], float(sys.argv[3])
    other = {}
    counts = executed_counts(path, binary, other)
    ins = disassembly(binary)
    total = flops = div = sqrt = mem_ops = mem_bytes = unknown = 0
    for a, c in counts.items():
        total += c
        if a not in ins:
            unknown += c
            continue
        mn, ops = ins[a]
        base = mn.replace("v", "", 1) if mn.startswith("v") else mn
        if base in SCALAR:
            flops += c
        elif base in PACKED:
            flops += 2 * c
        if base.startswith("div"):
            div += c * (2 if base.endswith("pd") else 1)
        if base.startswith("sqrt"):
            sqrt += c * (2 if base.endswith("pd") else 1)
        if "(" in ops and not mn.startswith("lea") and not mn.startswith("nop"):
            mem_ops += c
            mem_bytes += c * operand_bytes(base, ops)
    f = 1.0 / steps
    print(f"instructions        {total * f:10.1f} per particle-step")
    print(f"flops               {flops * f:10.1f} (scalar double; packed = 2)")
    print(f"  divisions         {div * f:10.1f}")
    print(f"  square roots      {sqrt * f:10.1f}")
    print(f"memory operands     {mem_ops * f:10.1f} ({mem_bytes * f:.0f} B through the core's loads and stores)")
    print(f"not disassembled    {unknown * f:10.1f}")
    for lib, c in sorted(other.items(), key=lambda kv: -kv[1]):
        if c * f >= 1.0:
            print(f"in {lib:16s} {c * f:10.1f} instructions (library calls: cbrt, pow, fmin, ...)")

if __name__ == "__main__":
    main()
