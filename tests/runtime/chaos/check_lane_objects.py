#!/usr/bin/env python3
"""Checks the object files of the batch lanes' ISA variants (cmake/npend_lanes.cmake): no
weak symbol outside an ISA namespace may hold AVX code.

A variant's unit is compiled for an ISA the CPU may lack. Its inline functions and template
instances are weak symbols, and the linker keeps one copy of each for every caller in the
program: a copy compiled for AVX-512 would then crash the baseline code on a CPU without it.
npend/batch_math.hpp prevents that by switching the ISA only after every other header, so
that only definitions in the ISA's own namespace (isa_avx2, isa_avx512f) or the unit's
anonymous namespace are compiled for it. This check finds a header that slipped in after the
switch. Usage: check_lane_objects.py OBJECT... (an argument may hold several, separated by
';', as CMake's $<TARGET_OBJECTS> gives them); exit 1 naming each offending symbol.
"""
import re
import subprocess
import sys

# VEX- and EVEX-encoded instructions (v...) and AVX-512's mask instructions (k...): none of
# them is in the baseline x86-64 (SSE2) code.
AVX_INSTRUCTION = re.compile(r"^\s+[0-9a-f]+:\s+(v|k)[a-z]")
FUNCTION = re.compile(r"^[0-9a-f]+ <(.+)>:$")
OWN_NAMESPACE = re.compile(r"isa_avx|_GLOBAL__N_")


def weak_symbols(obj):
    listing = subprocess.run(["nm", "--defined-only", obj], capture_output=True, text=True,
                             check=True).stdout
    return {parts[2] for parts in (line.split() for line in listing.splitlines())
            if len(parts) == 3 and parts[1] in ("W", "V", "u", "i")}


def offending(obj):
    weak = weak_symbols(obj)
    found, name = set(), None
    code = subprocess.run(["objdump", "-d", "--no-show-raw-insn", obj], capture_output=True,
                          text=True, check=True).stdout
    for line in code.splitlines():
        match = FUNCTION.match(line)
        if match:
            name = match.group(1)
        elif (name in weak and not OWN_NAMESPACE.search(name)
              and AVX_INSTRUCTION.match(line)):
            found.add(name)
    return found


def main(objects):
    if not objects:
        sys.exit("check_lane_objects.py: give the variants' object files")
    bad = [(obj, name) for obj in objects for name in sorted(offending(obj))]
    for obj, name in bad:
        print(f"{obj}: weak symbol {name} holds AVX code outside an ISA namespace")
    print(f"{len(objects)} objects checked, {len(bad)} offending symbols")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main([obj for arg in sys.argv[1:] for obj in arg.split(";") if obj]))
