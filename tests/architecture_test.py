#!/usr/bin/env python3
"""docs/architecture.md names every folder of the repository, and only folders that exist:
each backticked path ending in "/" must be a folder, and every folder holding tracked files
(git ls-files) must be named, but for the per-target folders of fuzz/corpus/ and
fuzz/regressions/, which their parent names.

Usage: architecture_test.py ROOT"""
import os
import re
import subprocess
import sys

root = sys.argv[1]
text = open(os.path.join(root, "docs", "architecture.md"), encoding="utf-8").read()
named = {m.rstrip("/") for m in re.findall(r"`([^`\s]+/)`", text)}
failures = [f"docs/architecture.md names {n}/, which is not a folder"
            for n in sorted(named) if not os.path.isdir(os.path.join(root, n))]
files = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True,
                       check=True).stdout.split("\n")
folders = {os.path.dirname(f) for f in files if f and os.path.dirname(f)}
for folder in sorted(folders):
    parent = os.path.dirname(folder)
    if parent in ("fuzz/corpus", "fuzz/regressions"):
        continue
    if folder not in named:
        failures.append(f"{folder}/ holds tracked files but docs/architecture.md does not name it")
for f in failures:
    print("FAIL:", f)
print(f"architecture: {len(named)} folders named, {len(folders)} hold tracked files")
sys.exit(1 if failures else 0)
