#!/usr/bin/python3
"""Runs the commands of a document as printed: every fenced block whose info string is `sh`, in order, as
one bash script per block (set -euo pipefail), in a scratch folder that stands for the repository's root
(examples/, scripts/ and tests/data/ of the source tree linked in, and ../shared beside it when the
project's shared folder exists), with `kincal` on the PATH. Later blocks see the files of earlier ones.

A block that reads ../shared/data is skipped, with a line saying so, when that folder is absent, and fails
instead when KINCAL_REQUIRE_DATA=1. A block fails when it exits non-zero or when a file it names after
--out is missing afterwards. Blocks of other info strings (`text`: synopses, outputs, file contents) are
not commands.

  run_doc_commands.py --kincal build/apps/kincal --source . README.md [--min-blocks N]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

FENCE = re.compile(r"^```(\S*)\s*$")


def blocks(path):
    """(line, info, text) of every fenced block of a Markdown file."""
    out, info, start, body = [], None, 0, []
    with open(path) as f:
        for n, line in enumerate(f, start=1):
            m = FENCE.match(line.rstrip("\n"))
            if info is None and m:
                info, start, body = m.group(1), n, []
            elif info is not None and line.rstrip("\n") == "```":
                out.append((start, info, "".join(body)))
                info = None
            elif info is not None:
                body.append(line)
    if info is not None:
        raise SystemExit(f"{path}:{start}:1: a fenced block that is never closed")
    return out


def scratch_root(source):
    """A folder holding repo/ (the cwd of the commands) and shared -> the project's shared folder."""
    root = tempfile.mkdtemp(prefix="kincal_doc_")
    repo = os.path.join(root, "repo")
    os.makedirs(os.path.join(repo, "tests"))
    for name in ("examples", "scripts"):
        os.symlink(os.path.join(source, name), os.path.join(repo, name))
    os.symlink(os.path.join(source, "tests", "data"), os.path.join(repo, "tests", "data"))
    shared = os.path.join(os.path.dirname(os.path.abspath(source)), "shared")
    if os.path.isdir(shared):
        os.symlink(shared, os.path.join(root, "shared"))
    bin_dir = os.path.join(root, "bin")
    os.makedirs(bin_dir)
    return root, repo, bin_dir


def outputs(text):
    return [m.group(1) for m in re.finditer(r"--out[ =](\S+)", text) if "$" not in m.group(1)]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kincal", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--min-blocks", type=int, default=0, help="fail unless the document has this many sh blocks")
    parser.add_argument("document")
    args = parser.parse_args()
    source = os.path.abspath(args.source)
    document = os.path.join(source, args.document)
    commands = [b for b in blocks(document) if b[1] == "sh"]
    if len(commands) < args.min_blocks:
        print(f"{args.document}: {len(commands)} sh blocks, expected at least {args.min_blocks}")
        return 1
    root, repo, bin_dir = scratch_root(source)
    os.symlink(os.path.abspath(args.kincal), os.path.join(bin_dir, "kincal"))
    have_data = os.path.isdir(os.path.join(root, "shared", "data"))
    require_data = os.environ.get("KINCAL_REQUIRE_DATA") == "1"
    env = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ.get("PATH", ""))
    ran = skipped = 0
    try:
        for line, _, text in commands:
            where = f"{args.document}:{line}"
            if "../shared/data" in text and not have_data:
                if require_data:
                    print(f"{where}: needs ../shared/data, absent, and KINCAL_REQUIRE_DATA=1")
                    return 1
                print(f"{where}: skipped: no ../shared/data beside the repository")
                skipped += 1
                continue
            result = subprocess.run(["bash", "-euo", "pipefail", "-c", text], cwd=repo, env=env,
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=900)
            missing = [f for f in outputs(text) if not os.path.exists(os.path.join(repo, f))]
            if result.returncode != 0 or missing:
                print(f"{where}: the block failed (exit {result.returncode}"
                      + (f"; missing {', '.join(missing)}" if missing else "") + "):\n" + text
                      + "--- its output:\n" + result.stdout)
                return 1
            print(f"{where}: ran")
            ran += 1
    finally:
        shutil.rmtree(root, ignore_errors=True)
    print(f"{args.document}: {ran} blocks ran, {skipped} skipped")
    return 0


if __name__ == "__main__":
    sys.exit(main())
