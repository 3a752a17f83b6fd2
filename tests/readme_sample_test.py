#!/usr/bin/env python3
"""README's embedding sample is the tested example's code: each block between a pair of
`// [name]` lines of examples/embed/main.cpp appears, dedented, verbatim in README.md."""
import re
import sys
import textwrap

source, readme = sys.argv[1], open(sys.argv[2]).read()
blocks = re.findall(r"^[ \t]*// \[(\w+)\]\n(.*?)^[ \t]*// \[\1\]\n", open(source).read(),
                    re.S | re.M)
if len(blocks) < 2:
    sys.exit("FAIL: fewer than two marked blocks in %s" % source)
for name, code in blocks:
    if textwrap.dedent(code) not in readme:
        sys.exit("FAIL: README.md lacks the example's [%s] block:\n%s" % (name, textwrap.dedent(code)))
    print("README has the example's [%s] block (%d lines)" % (name, code.count("\n")))
