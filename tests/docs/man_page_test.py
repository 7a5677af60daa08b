#!/usr/bin/env python3
"""The man page the build makes (cmake/ManPage.cmake) against the tool's own --help: it renders
without a warning, has a section for every command `shellcontract --help` lists, and names in that
section every option the command's --help prints (the option lines that tests/docs/
cli_reference_test.py reads, and every --option mentioned anywhere in the help); the DESCRIPTION
names every --option of `shellcontract --help`.

    man_page_test.py --cli build/shellcontract --page build/man/shellcontract.1 [--no-sweep]

The page is rendered by `man -l` (man-db) as a reader sees it, in the C locale so that a '\\-' is an
ASCII '-'; where groff is installed, `groff -man -ww -z` must also print no warning (a bad request
or escape). --no-sweep (a build without the Python module, which `sweep --help` needs): the sweep
section must exist, its options are not compared.

Exit status 0 when the page and the help agree, 1 with one line per difference.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cli_reference_test import OPTION_LINE, option_spellings  # noqa: E402

LONG_ANYWHERE = re.compile(r"(?<![\w-])--[a-z0-9][a-z0-9-]*")
# A command's section heading (.SS "shellcontract run") as man renders it: indented by 3.
SECTION = re.compile(r"^ {3}shellcontract ([a-z ]+?)\s*$")
# A section of the page (.SH), at column 0.
CHAPTER = re.compile(r"^[A-Z][A-Z ]*$")


def run(args, **kwargs):
    return subprocess.run(args, capture_output=True, text=True, timeout=120, **kwargs)


def help_text(cli, words):
    r = run([cli] + words + ["--help"], env=dict(os.environ, COLUMNS="80"))
    if r.returncode != 0:
        raise SystemExit("{} {} --help: exit code {}: {}".format(cli, " ".join(words), r.returncode,
                                                                 r.stderr.strip()))
    return r.stdout


def listed_commands(main_help):
    """The commands of `shellcontract --help`: the lower-case words that start each line of the
    list under 'commands:' ('run', 'bench ccd')."""
    commands, in_list = [], False
    for line in main_help.splitlines():
        if line == "commands:":
            in_list = True
        elif not line.strip():
            in_list = False
        elif in_list:
            m = re.match(r"  ([a-z]+(?: [a-z]+)*)(?: |$)", line)
            if m:
                commands.append(m.group(1))
    return commands


def help_options(text):
    """Every option a --help names: the spellings of its option lines, and each --option
    mentioned anywhere in it."""
    names = set(LONG_ANYWHERE.findall(text))
    for line in text.splitlines():
        m = OPTION_LINE.match(line)
        if m:
            head = re.split(r"\s{2,}", line.strip())[0]
            names.update(option_spellings(head))
    return names


def render(page):
    env = dict(os.environ, LC_ALL="C", MANWIDTH="80")
    env.pop("MANPAGER", None)
    env.pop("PAGER", None)
    if not shutil.which("man"):
        return "", ["man not found (Debian: man-db; scripts/install_deps.sh installs it)"]
    r = run(["man", "-l", page], env=env)
    problems = []
    if r.returncode != 0 or r.stderr.strip():
        problems.append("man -l {}: exit code {}: {}".format(page, r.returncode, r.stderr.strip()))
    groff = shutil.which("groff")
    if groff:
        g = run([groff, "-man", "-ww", "-z", "-Tutf8", page], env=env)
        if g.returncode != 0 or g.stderr.strip():
            problems.append("groff -man -ww: exit code {}: {}".format(g.returncode, g.stderr.strip()))
    return r.stdout, problems


def sections(rendered):
    """{'DESCRIPTION': text, 'run': text, ...}: the page's .SH chapters and its commands' .SS
    sections (a command's section ends at the next one or the next chapter)."""
    found, name, lines = {}, None, []
    for line in rendered.splitlines():
        m = SECTION.match(line)
        if m or CHAPTER.match(line):
            if name is not None:
                found[name] = "\n".join(lines)
            name, lines = (m.group(1) if m else line.strip()), []
        elif name is not None:
            lines.append(line)
    if name is not None:
        found[name] = "\n".join(lines)
    return found


def mentions(text, option):
    return re.search(r"(?<![\w-])" + re.escape(option) + r"(?![\w-])", text) is not None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", required=True)
    parser.add_argument("--page", required=True)
    parser.add_argument("--no-sweep", action="store_true")
    args = parser.parse_args()

    if not os.path.isfile(args.page):
        print("no man page at {} (the build makes it: cmake/ShellContractManPage.cmake)".format(args.page))
        return 1
    rendered, problems = render(args.page)
    found = sections(rendered)
    main_help = help_text(args.cli, [])
    commands = listed_commands(main_help)
    if not commands:
        problems.append("shellcontract --help lists no commands")
    for option in sorted(LONG_ANYWHERE.findall(main_help)):
        if not mentions(found.get("DESCRIPTION", ""), option):
            problems.append("DESCRIPTION does not name {} (shellcontract --help does)".format(option))
    for command in commands:
        if command not in found:
            problems.append("no section 'shellcontract {}' in the page".format(command))
            continue
        if command == "sweep" and args.no_sweep:
            print("sweep: not compared (no Python module in this build)")
            continue
        for option in sorted(help_options(help_text(args.cli, command.split()))):
            if not mentions(found[command], option):
                problems.append("section 'shellcontract {}' does not name {}".format(command, option))
    extra = set(found) - set(commands) - {"NAME", "SYNOPSIS", "DESCRIPTION", "COMMANDS"}
    for name in sorted(extra):
        problems.append("the page has a section '{}' that is no command of --help".format(name))
    for p in problems:
        print(p)
    if not problems:
        print("man page: {} commands, every option of their --help named".format(len(commands)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
