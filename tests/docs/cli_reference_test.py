#!/usr/bin/env python3
"""docs/cli.md against the tool's own --help: every option a subcommand's --help prints has a row
in that subcommand's section of docs/cli.md, and every row documents an option its --help prints.
For a command whose --help groups its options (run: cli/help_groups.hpp), each row sits under the
heading of its --help group. Where --help lists an option's values ("stvk | corotated | ..."; the
material names come from the registry), its row names every one of them in backquotes, so that a
new material or keyword does not leave the doc's list behind.

    cli_reference_test.py --cli build/shellcontract --doc docs/cli.md [--no-sweep]

docs/cli.md's layout, as read here: a section per command, headed "## `shellcontract COMMAND`"
(COMMAND as typed: "run", "bench ccd"); inside it, optional "### GROUP" headings named as --help
names its groups; an option's row is a table row whose first cell holds its spellings in
backquotes ("| `-p`, `--pressure` | ..."). Other mentions of an option (prose, other cells) are
not rows. --no-sweep (a build without the Python module, which `sweep --help` needs): the sweep
section is not compared, and the test says so.

Exit status 0 when the two agree, 1 with one line per difference.
"""

import argparse
import re
import subprocess
import sys

COMMANDS = ("run", "check", "repair", "regions", "reconstruct", "sweep", "bench ccd", "bench error")

# An option line of --help: two spaces, then the option (Boost: "-o [ --output ] FILE",
# "--json"; argparse: "-o DIR, --output DIR", "--workers WORKERS"). Wrapped help text is indented
# further, so a continuation that starts with "--thickness" is not an option line.
OPTION_LINE = re.compile(r"^  (-[A-Za-z0-9](?=[ ,\n]|$)|--[a-z0-9][a-z0-9-]*)")
LONG = re.compile(r"--([a-z0-9][a-z0-9-]*)")
SHORT = re.compile(r"(?<![\w-])-([A-Za-z0-9])(?![\w-])")
# A group heading of --help: a line at column 0 ending in ':' ("how much it contracts:",
# "options:"), followed by option lines.
GROUP_LINE = re.compile(r"^([a-z][^:]*):$")
# A list of values in an option's --help text: "stvk | corotated | linear" (and "on|off" in a
# value name); lower-case words only, so that "auto|none|FILE" lists auto and none. A value may be
# followed by what it means in parentheses: "isometric (the paper's, flat rest) | dihedral
# (rest-aware) | none" lists isometric, dihedral and none.
CHOICES = re.compile(r"[a-z0-9][a-z0-9-]*(?: \([^()]*\))?(?: ?\| ?[a-z0-9][a-z0-9-]*(?: \([^()]*\))?)+")
DESCRIPTION = re.compile(r" \([^()]*\)")
SECTION = re.compile(r"^## `shellcontract ([a-z ]+)`\s*$")
SUBSECTION = re.compile(r"^### (.+?)\s*$")
ROW = re.compile(r"^\|\s*(`-[^|]*)\|")


def option_spellings(text):
    """The option names in one option line's head or one row's first cell: long names, and
    short ones as '-x'."""
    names = ["--" + n for n in LONG.findall(text)]
    names += ["-" + s for s in SHORT.findall(LONG.sub("", text))]
    return names


def help_options(cli, command):
    """{option: group} of `shellcontract COMMAND --help` (group: the heading above it, or ''), and
    {option: [value, ...]} of the options whose help lists their values."""
    r = subprocess.run([cli] + command.split() + ["--help"], capture_output=True, text=True,
                       timeout=120)
    if r.returncode != 0:
        raise SystemExit("{} {} --help: exit code {}: {}".format(cli, command, r.returncode,
                                                                 r.stderr.strip()))
    out, group, text = {}, "", {}
    names = []  # the option line being read (its wrapped description follows, indented)
    for line in r.stdout.splitlines():
        g = GROUP_LINE.match(line)
        if g:
            group, names = g.group(1), []
            continue
        m = OPTION_LINE.match(line)
        if not m:
            if names and line.startswith("    "):
                for name in names:
                    text[name] += " " + line.strip()
            else:
                names = []
            continue
        # The head of the line: up to its default "(=...)" where it shows one (the description
        # may follow it after a single space), else up to the description (two spaces or more).
        # Boost writes the value name after the option (FILE, NAME (=mean)); argparse too
        # ("-o DIR, --output DIR"): only the dashed words are options.
        default = line.find(" (=")
        head = line[:default] if default >= 0 else re.split(r"\s{2,}", line.strip())[0]
        names = option_spellings(head)
        for name in names:
            out[name] = group
            text[name] = line.strip()
    if not out:
        raise SystemExit("{} --help printed no option lines; this test's parser is out of step "
                         "with it".format(command))
    choices = {}
    for name, t in text.items():
        for found in CHOICES.findall(t):
            values = DESCRIPTION.sub("", found).split("|")
            choices.setdefault(name, []).extend(v.strip() for v in values)
    return out, choices


def doc_options(path):
    """{command: {option: subsection}} of the rows of docs/cli.md, the problems found reading it
    (an option with two rows in one section), and {command: {option: its row's text}}."""
    sections, problems, rows = {}, [], {}
    command, sub = None, ""
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            s = SECTION.match(line)
            if s:
                command, sub = s.group(1).strip(), ""
                sections.setdefault(command, {})
                rows.setdefault(command, {})
                continue
            if line.startswith("## "):
                command = None  # a section that is not a command's
                continue
            t = SUBSECTION.match(line)
            if t:
                sub = t.group(1).strip()
                continue
            row = ROW.match(line)
            if row and command is not None:
                for name in option_spellings(row.group(1)):
                    if name in sections[command]:
                        problems.append("{}:{}: `{} {}` has a second row".format(
                            path, number, command, name))
                    sections[command][name] = sub
                    rows[command][name] = line
    return sections, problems, rows


def compare(command, printed, documented, choices=None, rows=None):
    """The differences of one command, as lines."""
    lines = []
    for name, values in sorted((choices or {}).items()):
        row = (rows or {}).get(name)
        missing = [v for v in values if row is not None and "`{}`".format(v) not in row]
        if missing:
            lines.append("`{} {}`: --help lists {} but its row in docs/cli.md does not name {}".format(
                command, name, " | ".join(values), ", ".join("`{}`".format(v) for v in missing)))
    for name in sorted(set(printed) - set(documented)):
        lines.append("`{} {}` is printed by --help but has no row in docs/cli.md".format(
            command, name))
    for name in sorted(set(documented) - set(printed)):
        lines.append("`{} {}` has a row in docs/cli.md but no --help prints it".format(
            command, name))
    if len(set(printed.values())) > 1:  # --help groups its options: the doc follows its groups
        for name in sorted(set(printed) & set(documented)):
            if printed[name] != documented[name]:
                lines.append("`{} {}` is under '### {}' in docs/cli.md; --help has it under "
                             "'{}'".format(command, name, documented[name], printed[name]))
    return lines


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cli", required=True)
    p.add_argument("--doc", required=True)
    p.add_argument("--no-sweep", action="store_true")
    args = p.parse_args(argv)
    try:
        documented, problems, rows = doc_options(args.doc)
    except OSError as e:
        print("cannot read {}: {}".format(args.doc, e.strerror), file=sys.stderr)
        return 1
    for command in COMMANDS:
        if command == "sweep" and args.no_sweep:
            print("sweep: not compared (built without the Python module that `sweep --help` "
                  "needs)")
            continue
        if command not in documented:
            problems.append("docs/cli.md has no section '## `shellcontract {}`'".format(command))
            continue
        printed, choices = help_options(args.cli, command)
        problems += compare(command, printed, documented[command], choices, rows[command])
    for command in sorted(set(documented) - set(COMMANDS)):
        problems.append("docs/cli.md has a section for `{}`, which is not a command this test "
                        "knows (add it to COMMANDS)".format(command))
    for line in problems:
        print(line, file=sys.stderr)
    if not problems:
        print("docs/cli.md documents exactly the options of {} commands' --help".format(
            len(COMMANDS) - args.no_sweep))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
