#!/usr/bin/env bash
# Checks that the scalar traversal kernels contain no SIMD arithmetic: no packed float, double or
# integer operation (addps, mulpd, vfmadd231ps, paddd, ...) and no 256- or 512-bit register.
# Scalar SSE arithmetic (addss, mulsd) is how x86-64 computes with one float, and moves, bitwise
# and/or/xor (fabs, negation) and the zero and all-ones idioms (pxor, pcmpeqd of a register with
# itself) compute nothing in parallel, so they pass.
#
# Usage: scripts/check_scalar_kernels.sh KERNELS_SCALAR_OBJECT [LINKED_BINARY]
#   KERNELS_SCALAR_OBJECT  the object file of libsplitgrid/src/kernels/kernels_scalar.cpp: every
#                          function in it is checked
#   LINKED_BINARY          a program linked with the library: its copies of the scalar kernels and
#                          of the inline helpers they call (which the linker may have taken from
#                          another, vectorised, object) are checked too
# Exit codes: 0 no SIMD arithmetic, 1 usage, 2 a file cannot be read, 3 SIMD arithmetic found
# (each offending instruction printed with its function).
# Not on x86-64 (no such instructions there) the check is skipped with exit code 0.
set -euo pipefail

if (($# < 1 || $# > 2)); then
    echo "usage: check_scalar_kernels.sh KERNELS_SCALAR_OBJECT [LINKED_BINARY]" >&2
    exit 1
fi
for file in "$@"; do
    if [[ ! -r "${file}" ]]; then
        echo "check_scalar_kernels.sh: cannot read ${file}" >&2
        exit 2
    fi
done
object="$1"
binary="${2:-}"
if ! objdump -f "${object}" | grep -q 'x86-64'; then
    echo "check_scalar_kernels.sh: ${object} is not x86-64 code; nothing to check"
    exit 0
fi

# Prints "function: instruction" for every SIMD instruction in the functions of `disassembly`
# (objdump -d, mangled names) that `wanted` accepts (all when the list is empty).
find_simd() {
    local wanted_list="$1"
    awk -v wanted_list="${wanted_list}" '
        BEGIN {
            n = split(wanted_list, names, "\n")
            for (i = 1; i <= n; ++i) if (names[i] != "") wanted[names[i]] = 1
            check_all = (n == 0 || wanted_list == "")
        }
        /^[0-9a-f]+ <.*>:$/ {
            name = $2; sub(/^</, "", name); sub(/>:$/, "", name)
            checking = check_all || (name in wanted) || name ~ /^_ZN2sg7kernels6scalar/
            next
        }
        !checking { next }
        /^ *[0-9a-f]+:\t/ {
            split($0, parts, "\t")
            insn = parts[2]
            mnemonic = insn; sub(/ .*/, "", mnemonic)
            operands = insn; sub(/^[^ ]* */, "", operands)
            bad = 0
            if (insn ~ /%[yz]mm/) bad = 1
            else if (mnemonic ~ /^v?(mov|and|andn|or|xor)[a-z]*p[sd]$/) bad = 0
            else if (mnemonic ~ /p[sd]$/) bad = 1
            else if (mnemonic ~ /^v?(pxor|pcmpeq[bwdq])$/) {
                split(operands, regs, ",")
                bad = !(regs[1] == regs[2])  # the zero and all-ones idioms
            }
            else if (mnemonic ~ /^v?p(add|sub|mul|madd|min|max|avg|sad|abs|sign|sll|srl|sra|cmp|shuf|blend|perm|unpck|pack|and|or|hadd|hsub|test|movmsk|ext|ins|broadcast|gather)/) bad = 1
            else if (mnemonic ~ /^v(gather|scatter|perm|broadcast|fn?m(add|sub))/) bad = 1
            if (bad) { print name ": " insn; ++found }
        }
        END { exit found > 0 ? 3 : 0 }
    '
}

status=0
objdump -d --no-show-raw-insn "${object}" | find_simd "" || status=$?
if [[ -n "${binary}" ]]; then
    # The helpers the kernels call, defined weak in the object: the linker keeps one copy.
    helpers="$(nm --defined-only "${object}" | awk '$2 == "W" || $2 == "T" { print $3 }')"
    objdump -d --no-show-raw-insn "${binary}" | find_simd "${helpers}" || status=$?
fi
if ((status == 3)); then
    echo "check_scalar_kernels.sh: SIMD arithmetic in the scalar kernels (above)" >&2
    exit 3
fi
if ((status != 0)); then exit 3; fi
echo "check_scalar_kernels.sh: no SIMD arithmetic in the scalar kernels"
