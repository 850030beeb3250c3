#!/usr/bin/env python3
"""Every command-line option a user reads of exists (issue 52 item 6). tests/CMakeLists.txt
registers each check as a ctest test, label "integration". Usage: options_test.py CHECK SOURCE_DIR
BUILD_DIR

  help_in_docs    each program's options, as its --help lists them (sweepd; sweepctl and every
                  subcommand; render_frames; stream_poses in C++; stream_poses.py's argparse
                  definitions), are named on the docs page that documents that program
  docs_options    every --option a docs page, README.md, deploy/README.md or protocol/README.md
                  names is an option of one of the project's programs (the four above, the
                  benchmarks) or of an external tool listed in EXTERNAL; in a ```sh block, an
                  option after a project program (and its subcommand) is that program's
  hints           every --option in a string literal of the programs' sources (what they print:
                  hints, errors, help) is an option of the program that prints it, or of the
                  program the text names just before it ("sweepd's --tls-cert"); every request
                  field a string names (`UploadClip.range_of_motion`, `LoadModel.options.rig_map_json`)
                  is one of protocol/sweepd.fbs; every `make TARGET` a string or a docs page names
                  (in code) is a target of the Makefile
"""
import pathlib
import re
import shlex
import subprocess
import sys

# An option: two dashes, a lowercase letter, then letters, digits, '-' or '_' (gtest's).
OPTION = re.compile(r"(?<![\w-])--[a-z][a-z0-9_-]*[a-z0-9]")

# Options of tools that are not the project's, which the docs and sources name, each with its
# tool: a made-up option of ours must not hide among them.
EXTERNAL = {
    "cmake": ["--preset", "--build", "--target", "--install", "--component", "--prefix"],
    "python3 -m venv / pip": ["--system-site-packages", "--no-index", "--no-build-isolation"],
    "flatc": ["--ts", "--cpp", "--python"],
    "mkdocs": ["--strict"],
    "blender": ["--factory-startup", "--python", "--python-exit-code"],
    "chromium": ["--use-angle", "--enable-unsafe-swiftshader"],
    "GoogleTest": ["--gtest_filter"],
    "Google Benchmark": ["--benchmark_filter", "--benchmark_min_time", "--benchmark_repetitions"],
    "git": ["--short"],
    "valgrind (callgrind)": ["--toggle-collect"],
    "docker / podman": ["--build-arg", "--isolation", "--variant"],
    "kubectl": ["--dry-run", "--from-file", "--validate", "--for"],
    "systemd-analyze / systemctl": ["--now", "--offline"],
}
EXTERNAL_OPTIONS = {option for options in EXTERNAL.values() for option in options}

# "--flag" is the placeholder of sweepctl's message format ("sweepctl COMMAND: --flag: reason").
PLACEHOLDERS = {"--flag"}

# The page that documents each program.
PAGES = {"sweepd": "docs/daemon.md", "sweepctl": "docs/sweepctl.md",
         "render_frames": "docs/clients.md", "stream_poses": "docs/daemon.md",
         "stream_poses.py": "docs/daemon.md"}

# Which programs print the strings of each source folder or file (the longest prefix wins).
# Libraries shared by several programs must name only options all of them have.
CLIENTS = ["sweepctl", "render_frames", "stream_poses"]
SOURCE_PROGRAMS = {
    "cli": ["sweepctl"], "server": ["sweepd"], "client": CLIENTS, "console": CLIENTS + ["sweepd"],
    "client_examples/render_frames.cpp": ["render_frames"],
    "client_examples/stream_poses.cpp": ["stream_poses"],
    "client_examples/stream_poses.py": ["stream_poses.py"],
    "client_examples/clip_file_flags.cpp": ["render_frames", "stream_poses"],
    "client_examples/clip_file_flags.h": ["render_frames", "stream_poses"],
    "gpu/sheet": ["sweepctl"],  # sweepctl sheet and check draw locally; sweepd's errors echo its fields
    "selfcheck": ["sweepctl"],
}
# Folders whose strings no user reads from a program (tests break things on purpose), or not ours.
NOT_PRINTED = {"build", "tests", "fuzz", "node_modules"}
# Folders of libraries the command line and the daemon both link.
LIBRARY_FOLDERS = ["deform", "motion", "io", "metrics", "mannequin", "gpu"]


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    return 1


def help_text(*command):
    run = subprocess.run([*map(str, command), "--help"], capture_output=True, text=True, timeout=60)
    if run.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, command))} --help exited {run.returncode}: {run.stderr}")
    return run.stdout


def listed_options(help_page):
    """The options a --help defines: the first column of its option lines (CLI11's
    `-h,--help`, `--adapt,--no-adapt{false}`; sweepd's `  --port N`), not those its prose names."""
    options = set()
    for line in help_page.split("\n"):
        found = re.match(r"\s+(-[^\s]*)", line)
        if found:
            options.update(o for o in OPTION.findall(found.group(1)))
    return options


def defined_in_source(path):
    """Options a program without a built --help defines: argparse, CLI11 and argv comparisons."""
    text = path.read_text(encoding="utf-8")
    options = set()
    for names in re.findall(r"(?:add_argument|add_option|add_flag)\(\s*\"([^\"]+)\"", text):
        options.update(OPTION.findall(names))
    options.update(re.findall(r"strcmp\(argv\[i\], \"(--[\w-]+)\"\)", text))
    return options


def program_options(source, build):
    """{program: {option}}: sweepctl's are those of the command and every subcommand."""
    programs = {"sweepd": listed_options(help_text(build / "server/sweepd")),
                "render_frames": listed_options(help_text(build / "client_examples/render_frames")),
                "stream_poses": listed_options(help_text(build / "client_examples/stream_poses"))}
    sweepctl = build / "cli/sweepctl"
    top = help_text(sweepctl)
    subcommands = re.findall(r"^  ([a-z][\w-]*)\s", top.split("Subcommands:")[1], re.M)
    programs["sweepctl"] = listed_options(top)
    programs["sweepctl subcommands"] = {}
    for subcommand in subcommands:
        options = listed_options(help_text(sweepctl, subcommand))
        programs["sweepctl subcommands"][subcommand] = options | programs["sweepctl"]
        programs["sweepctl"] |= options
    programs["stream_poses.py"] = defined_in_source(source / "client_examples/stream_poses.py") | {"--help"}
    for bench in sorted((source / "bench").glob("*")):
        if bench.suffix in (".cpp", ".py") and defined_in_source(bench):
            programs[bench.stem] = defined_in_source(bench) | {"--help"}
    programs["sweepd"].add("--help")  # sweepd's own help does not list itself
    return programs


def every_option(programs):
    options = set(EXTERNAL_OPTIONS | PLACEHOLDERS)
    for name, found in programs.items():
        if name != "sweepctl subcommands":
            options |= found
    return options


def help_in_docs(source, build):
    programs = program_options(source, build)
    errors = 0
    for program, page in PAGES.items():
        named = set(OPTION.findall((source / page).read_text(encoding="utf-8")))
        missing = sorted(programs[program] - named - {"--help"})
        for option in missing:
            errors += fail(f"{program} --help lists {option}, which {page} does not name")
        print(f"{program}: {len(programs[program])} options, {len(missing)} not named on {page}")
    return 1 if errors else 0


def program_of_command(words, programs):
    """(program, options) a shell command runs, or None for commands not the project's."""
    if not words:
        return None
    name = pathlib.PurePath(words[0]).name
    if name == "python3" and len(words) > 1:
        name = pathlib.PurePath(words[1]).name
        words = words[1:]
    if name == "sweepctl":
        subcommand = next((w for w in words[1:] if not w.startswith("-")), None)
        by_subcommand = programs["sweepctl subcommands"]
        if subcommand in by_subcommand:
            return f"sweepctl {subcommand}", by_subcommand[subcommand]
        return name, programs["sweepctl"]
    if name in programs and name != "sweepctl subcommands":
        return name, programs[name]
    return None


def shell_commands(text):
    """Each command line of the page's ```sh blocks, continuation lines joined and the block's
    variables (`S=build/release/cli/sweepctl`) expanded."""
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        variables = {}
        for line in block.replace("\\\n", " ").split("\n"):
            assignment = re.fullmatch(r"\s*([A-Za-z_]\w*)=(\S+)\s*", line)
            if assignment:
                variables[assignment.group(1)] = assignment.group(2)
                continue
            line = re.sub(r"\$(\w+)", lambda m: variables.get(m.group(1), m.group(0)), line)
            for command in re.split(r"&&|;|\|", line):
                try:
                    yield shlex.split(command, comments=True)
                except ValueError:
                    yield command.split()


def docs_options(source, build):
    programs = program_options(source, build)
    known = every_option(programs)
    pages = sorted((source / "docs").glob("*.md")) + [source / "README.md", source / "deploy/README.md",
                                                       source / "protocol/README.md"]
    targets = make_targets(source)
    errors = 0
    for page in pages:
        text = page.read_text(encoding="utf-8")
        relative = page.relative_to(source)
        for target in wrong_make_targets(text, targets):
            errors += fail(f"{relative} names `make {target}`, which the Makefile does not have")
        for option in sorted(set(OPTION.findall(text)) - known):
            errors += fail(f"{relative} names {option}, which no program of the project (nor a tool in "
                           f"EXTERNAL) has")
        for words in shell_commands(text):
            found = program_of_command(words, programs)
            if found is None:
                continue
            program, options = found
            for option in sorted({o for w in words for o in OPTION.findall(w.split("=")[0])} - options):
                errors += fail(f"{relative}: `{' '.join(words)}`: {option} is not an option of {program}")
    print(f"{len(pages)} pages checked against {len(known)} options")
    return 1 if errors else 0


def schema_tables(source):
    """{table or struct: {field: type}} of protocol/sweepd.fbs."""
    tables, current = {}, None
    for line in (source / "protocol/sweepd.fbs").read_text(encoding="utf-8").split("\n"):
        line = line.split("//")[0].strip()
        opened = re.match(r"(?:table|struct) (\w+)", line)
        if opened:
            current = tables.setdefault(opened.group(1), {})
        elif line.startswith("}"):
            current = None
        elif current is not None:
            field = re.match(r"(\w+)\s*:\s*\[?(\w+)", line)
            if field:
                current[field.group(1)] = field.group(2)
    return tables


def wrong_field(tables, path):
    """Why `Table.field.field` names no field of the schema, or None."""
    names = path.split(".")
    table = names[0]
    for field in names[1:]:
        if field not in tables.get(table, {}):
            return f"{table} has no field {field}"
        table = tables[table][field]
    return None


def make_targets(source):
    return set(re.findall(r"^([a-z][\w-]*):", (source / "Makefile").read_text(encoding="utf-8"), re.M))


def wrong_make_targets(text, targets):
    """`make X` in the text's code (spans and ```sh blocks) whose X is not a target."""
    code = " ".join(re.findall(r"```sh\n(.*?)```", text, re.S) + re.findall(r"`([^`\n]+)`", text))
    return sorted(set(re.findall(r"(?<![\w-])make ([a-z][\w-]*)", code)) - targets)


def programs_of_source(relative):
    best = max((prefix for prefix in SOURCE_PROGRAMS
                if relative == prefix or relative.startswith(prefix + "/")), key=len, default=None)
    if best is not None:
        return SOURCE_PROGRAMS[best]
    if relative.split("/")[0] in LIBRARY_FOLDERS:
        return ["sweepctl", "sweepd"]
    return None


def string_literals(line, suffix):
    if suffix == ".py":
        return [a or b for a, b in re.findall(r'"((?:[^"\\]|\\.)*)"|\'((?:[^\'\\]|\\.)*)\'', line)]
    return re.findall(r'"((?:[^"\\]|\\.)*)"', line)


def hints(source, build):
    programs = program_options(source, build)
    # "sweepd's --tls-cert", "sweepctl check --sheet", "sweepd's Unix socket (its --unix-socket)"
    named_before = re.compile(r"(sweepd|sweepctl|render_frames|stream_poses)(?:'s)?\s+(?:[\w-]+\s+){0,2}"
                              r"(?:\(its\s+)?$")
    tables, targets = schema_tables(source), make_targets(source)
    errors, checked = 0, 0
    for path in sorted(source.rglob("*")):
        relative = path.relative_to(source).as_posix()
        if path.suffix not in (".cpp", ".h", ".py", ".sh") or relative.split("/")[0] in NOT_PRINTED \
                or relative.startswith("."):
            continue
        owners = programs_of_source(relative)
        for number, line in enumerate(path.read_text(encoding="utf-8").split("\n"), 1):
            if line.lstrip().startswith(("//", "#")):
                continue
            for literal in string_literals(line, path.suffix):
                for target in wrong_make_targets(literal, targets):  # in backquotes only
                    errors += fail(f"{relative}:{number}: `make {target}`: no such target: \"{literal}\"")
                for field in re.findall(r"(?<![\w.])((?:[A-Z]\w+)(?:\.[a-z_]\w*)+)", literal):
                    if field.split(".")[0] in tables:
                        checked += 1
                        why = wrong_field(tables, field)
                        if why:
                            errors += fail(f"{relative}:{number}: {field}: {why}: \"{literal}\"")
                if owners is None:
                    continue
                for found in OPTION.finditer(literal):
                    option, checked = found.group(0), checked + 1
                    qualifier = named_before.search(literal[:found.start()])
                    printers = [qualifier.group(1)] if qualifier else owners
                    for program in printers:
                        if option not in programs[program] and option not in EXTERNAL_OPTIONS:
                            errors += fail(f"{relative}:{number}: {option} is not an option of {program}: "
                                           f"\"{literal}\"")
    print(f"{checked} options and request fields named in string literals checked")
    return 1 if errors else 0


if __name__ == "__main__":
    checks = {"help_in_docs": help_in_docs, "docs_options": docs_options, "hints": hints}
    if len(sys.argv) != 4 or sys.argv[1] not in checks:
        sys.exit(__doc__)
    sys.exit(checks[sys.argv[1]](pathlib.Path(sys.argv[2]).resolve(), pathlib.Path(sys.argv[3]).resolve()))
