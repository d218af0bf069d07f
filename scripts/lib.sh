# shellcheck shell=bash
# hairscatter scripts: helpers shared by scripts/*.sh (sourced, not run).
#
#   source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
#
# Every script documents itself in the comment block after its shebang; --help prints
# that block, so the usage text is written once, where the script is read.

# The comment block after line 1 of FILE, without the leading "# ".
_hs_header() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$1"; }

# hs_usage: print the calling script's usage (its header comment) on stdout.
hs_usage() { _hs_header "${BASH_SOURCE[1]}"; }

# hs_usage_error MESSAGE...: the message and the calling script's usage on stderr; exit 2.
hs_usage_error() {
    echo "$(basename "${BASH_SOURCE[1]}"): $*" >&2
    _hs_header "${BASH_SOURCE[1]}" >&2
    exit 2
}

# hs_no_args "$@": for a script that takes no arguments: --help prints its usage and exits 0,
# anything else is a usage error.
hs_no_args() {
    local script="${BASH_SOURCE[1]}"
    case "${1:-}" in
        "") ;;
        -h | --help) _hs_header "$script"; exit 0 ;;
        *)
            echo "$(basename "$script"): unknown argument '$1'" >&2
            _hs_header "$script" >&2
            exit 2
            ;;
    esac
}

# hs_cpu_line: the CPU for a results header: lscpu's model name, the family and model
# numbers (/proc/cpuinfo) and, for AMD's, the core generation, then the core count. VMs
# often name every AMD part "AMD EPYC", and the generations differ by more than a change
# in the code (the tabulated bound eval read 0.94 u on a Zen 4 and 0.58 u on a Zen 5).
hs_cpu_line() {
    local name family model vendor gen=""
    name="$(lscpu 2>/dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -1)"
    family="$(sed -n 's/^cpu family[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo 2>/dev/null | head -1)"
    model="$(sed -n 's/^model[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo 2>/dev/null | head -1)"
    vendor="$(sed -n 's/^vendor_id[[:space:]]*:[[:space:]]*//p' /proc/cpuinfo 2>/dev/null | head -1)"
    if [[ $vendor == AuthenticAMD && -n $family && -n $model ]]; then
        case "$family" in
            23) gen="Zen or Zen 2" ;;
            25) if (( (model >= 16 && model < 32) || (model >= 96 && model < 128) || (model >= 160 && model < 176) )); then
                    gen="Zen 4"
                else
                    gen="Zen 3"
                fi ;;
            26) gen="Zen 5" ;;
        esac
    fi
    echo "${name:-unknown CPU} (family ${family:-?}, model ${model:-?}${gen:+: $gen}), $(nproc) cores"
}

# hs_native_has_avx512 CXX: whether CXX's -march=native targets AVX-512, which valgrind
# (3.19 to 3.22) cannot run: the instruction counts (icount.sh, bench.sh) build for
# x86-64-v3 there. (The macros are read into a variable, not piped into grep -q: under
# pipefail the compiler's SIGPIPE would make the test fail at random.)
hs_native_has_avx512() {
    local defs
    defs="$("$1" -march=native -dM -E -x c++ /dev/null)" || return 1
    [[ $defs == *__AVX512F__* ]]
}
