#!/usr/bin/python3
"""Every symbol a library defines belongs to namespace lava, to a dependency (std, toml++,
glm, Highway) or to the toolchain (crt, unwinding, switch tables). Reads `nm --defined-only`.

    check_symbols.py liblava.so   -> exit 0, or 1 listing the strangers
"""
import re
import subprocess
import sys

ALLOWED_NAMESPACES = {"lava", "std", "toml", "glm", "hwy", "__gnu_cxx", "__cxxabiv1"}
TOOLCHAIN = re.compile(
    r"^(_DYNAMIC|_GLOBAL_OFFSET_TABLE_|__FRAME_END__|__GNU_EH_FRAME_HDR|__TMC_END__|"
    r"__do_global_dtors_aux(_fini_array_entry)?|__dso_handle|__frame_dummy_init_array_entry|"
    r"_init|_fini|frame_dummy|register_tm_clones|deregister_tm_clones|completed\.\d+|"
    r"__tcf_\d+|CSWTCH\.\d+|DW\.ref\..*|_GLOBAL__sub_I_.*|__bss_start|_edata|_end|"
    r"_sub_[DI]_\d+_\d+)$")  # the last: a sanitized build's module constructors
STD_ABBREVIATIONS = ("St", "Sa", "Sb", "Ss", "Si", "So", "Sd")


def first_namespace(mangled):
    """The outermost scope of an Itanium-mangled name, or None for a global name."""
    s = mangled[2:]  # after _Z
    s = re.sub(r"^(TV|TI|TS|TT|GV|GR|Th-?n?\d+_|Tv-?n?\d+_-?n?\d+_|Tc.*?_.*?_)", "", s)
    while s and s[0] in "NZ":  # nested name, or a local entity of a function
        s = s[1:]
        s = re.sub(r"^[rVKOR]+", "", s)
    if s.startswith(STD_ABBREVIATIONS):
        return "std"
    match = re.match(r"^(\d+)", s)
    if not match:
        return None
    length = int(match.group(1))
    return s[len(match.group(1)):len(match.group(1)) + length]


def main(path):
    out = subprocess.run(["nm", "--defined-only", path], check=True, capture_output=True,
                         text=True).stdout
    strangers = []
    for line in out.splitlines():
        parts = line.split()
        if len(parts) < 3:
            continue
        name = parts[2]
        if name.startswith("_Z"):
            scope = first_namespace(name.split("@")[0].split(".")[0])
            if scope in ALLOWED_NAMESPACES:
                continue
        elif TOOLCHAIN.match(name):
            continue
        strangers.append(name)
    if strangers:
        demangled = subprocess.run(["c++filt"], input="\n".join(strangers), capture_output=True,
                                   text=True).stdout.splitlines()
        print(f"{path}: {len(strangers)} symbols outside namespace lava and its dependencies:")
        for s in demangled[:40]:
            print("  " + s)
        return 1
    print(f"{path}: every defined symbol is lava's, a dependency's or the toolchain's")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
