#!/usr/bin/env python3
"""The docs site's tests (tests/CMakeLists.txt registers each check as a ctest test, label
"integration"). Usage: docs_site_test.py CHECK SOURCE_DIR [BUILD_DIR]

  mkdocs_strict    `mkdocs build --strict` of mkdocs.yml into a temporary folder: any warning fails
                   (a broken link between pages, a page missing from the site, a snippet not found)
  readme_links     README.md begins with the `make demo` / `make test` block; every relative link
                   and image of README.md names a file of the tree
  getting_started  every ```sh block of docs/getting-started.md names what exists: make targets in
                   the Makefile, scripts in the tree, built programs (BUILD_DIR) with the
                   subcommands and flags their --help lists; the blocks marked
                   `<!-- test: run -->` (cheap) are run in a scratch folder as the page shows them
"""
import os
import pathlib
import re
import shlex
import subprocess
import sys
import tempfile


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    return 1


def mkdocs_strict(source, _build):
    with tempfile.TemporaryDirectory(prefix="sweepd-docs-site-") as site:
        try:
            run = subprocess.run(["mkdocs", "build", "--strict", "--config-file", str(source / "mkdocs.yml"),
                                  "--site-dir", site], cwd=source, capture_output=True, text=True, timeout=300,
                                 env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"})  # no __pycache__ in the tree
        except FileNotFoundError:
            return fail("no mkdocs: deploy/install-deps.sh installs Debian's mkdocs and mkdocs-material")
        print(run.stdout + run.stderr)
        warnings = [line for line in (run.stdout + run.stderr).splitlines() if line.lstrip().startswith(("WARNING", "ERROR"))]
        if run.returncode != 0 or warnings:
            return fail(f"mkdocs build --strict exited {run.returncode}: " + "; ".join(warnings))
        for page in ("index.html", "getting-started.html", "testing.html"):
            if not (pathlib.Path(site) / page).is_file():
                return fail(f"the site has no {page}")
        if "make sanitize-untrusted" not in (pathlib.Path(site) / "testing.html").read_text(encoding="utf-8"):
            return fail("testing.html lacks README's table of test targets (mkdocs_hooks.py)")
    return 0


def readme_links(source, _build):
    text = (source / "README.md").read_text(encoding="utf-8")
    lines = text.split("\n")
    if lines[1:6] != ["", "```sh", lines[3], lines[4], "```"] or not lines[3].startswith("make demo ") \
            or not lines[4].startswith("make test "):
        return fail("README.md must begin with its title and the ```sh block of `make demo` and `make test`")
    if len(lines) > 201:
        return fail(f"README.md has {len(lines) - 1} lines; the limit is 200 (the rest belongs in docs/)")
    errors = 0
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+://|#|mailto:", target):
            continue
        path = source / target.split("#")[0]
        if not path.exists():
            errors += fail(f"README.md links to {target}, which does not exist")
    return 1 if errors else 0


def sh_blocks(page):
    """(run marker or None, [lines]) for each ```sh block of the page."""
    blocks, marker, block = [], None, None
    for line in page.read_text(encoding="utf-8").split("\n"):
        if block is not None:
            if line.strip() == "```":
                blocks.append((marker, block))
                block, marker = None, None
            else:
                block.append(line)
        elif line.strip() == "```sh":
            block = []
        elif line.strip():
            found = re.fullmatch(r"<!-- test: (run[^>]*) -->", line.strip())
            marker = found.group(1) if found else None
    return blocks


def help_text(program, *args):
    run = subprocess.run([str(program), *args, "--help"], capture_output=True, text=True, timeout=60)
    return run.stdout + run.stderr


def check_line(words, source, build):
    """Errors (strings) for one command of a block, its variables already expanded."""
    command, args = words[0], words[1:]
    if command == "make":
        makefile = (source / "Makefile").read_text(encoding="utf-8")
        return [f"make {t}: no such target in the Makefile" for t in args
                if not t.startswith("-") and not re.search(rf"^{re.escape(t)}:", makefile, re.M)]
    if command == "bash":
        return [] if (source / args[0]).is_file() else [f"bash {args[0]}: no such file"]
    if command.startswith("build/release/"):
        program = build / command[len("build/release/"):]
        if not os.access(program, os.X_OK):
            return [f"{command}: {program} is not built"]
        sub = []
        if args and not args[0].startswith("-"):
            subcommands = help_text(program)
            if not re.search(rf"^\s+{re.escape(args[0])}\s", subcommands, re.M):
                return [f"{command} {args[0]}: not a subcommand its --help lists"]
            sub = [args[0]]
        usage = help_text(program, *sub)
        return [f"{' '.join([command, *sub])} {flag}: not a flag its --help lists"
                for flag in (a.split("=")[0] for a in args if a.startswith("--"))
                if not re.search(rf"{re.escape(flag)}(?![\w-])", usage)]
    return [f"{command}: the test does not know how to check this command; teach tests/docs/docs_site_test.py"]


def getting_started(source, build):
    page = source / "docs" / "getting-started.md"
    blocks = sh_blocks(page)
    if not blocks:
        return fail(f"{page} has no ```sh block")
    errors, ran = [], 0
    shared = (source / ".." / "shared" / "data").resolve()
    for marker, block in blocks:
        variables = {}
        for line in block:
            words = shlex.split(line, comments=True)
            if not words:
                continue
            if len(words) == 1 and re.fullmatch(r"[A-Za-z_]\w*=\S+", words[0]):
                name, value = words[0].split("=", 1)
                variables[name] = value
                continue
            words = [re.sub(r"\$(\w+)", lambda m: variables.get(m.group(1), m.group(0)), w) for w in words]
            errors += [f"`{line.strip()}`: {e}" for e in check_line(words, source, build)]
        if marker is None:
            continue
        allowed = {0}
        found = re.search(r"exit status ([\d or]+)", marker)
        if found:
            allowed = {int(n) for n in re.findall(r"\d+", found.group(1))}
        if not shared.is_dir():
            print(f"skipped running a block: no {shared} beside the checkout")
            continue
        script = "\n".join(block).replace("build/release/", f"{build}/").replace("../shared/data", str(shared))
        with tempfile.TemporaryDirectory(prefix="sweepd-getting-started-") as scratch:
            run = subprocess.run(["bash", "-e", "-c", script], cwd=scratch, capture_output=True, text=True,
                                 timeout=600)
        ran += 1
        print(f"ran ({marker}), exit status {run.returncode}:\n{script}")
        if run.returncode not in allowed:
            errors.append(f"block exited {run.returncode} (expected {sorted(allowed)}):\n{script}\n"
                          f"{run.stdout[-3000:]}{run.stderr[-3000:]}")
    for e in errors:
        fail(e)
    print(f"{len(blocks)} blocks checked, {ran} run")
    return 1 if errors else 0


if __name__ == "__main__":
    checks = {"mkdocs_strict": mkdocs_strict, "readme_links": readme_links, "getting_started": getting_started}
    if len(sys.argv) < 3 or sys.argv[1] not in checks:
        sys.exit(__doc__)
    build_dir = pathlib.Path(sys.argv[3]).resolve() if len(sys.argv) > 3 else None
    sys.exit(checks[sys.argv[1]](pathlib.Path(sys.argv[2]).resolve(), build_dir))
