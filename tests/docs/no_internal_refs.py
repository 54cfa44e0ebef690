#!/usr/bin/env python3
"""User-facing text carries no internal work references.

Scanned: README.md, every Markdown page under docs/, studies/*.toml (comments, descriptions,
titles, labels, citations) and studies/reference/* (for a .csv file only its comment lines, the
ones starting with '#': the data rows are transcribed as published and are not checked).

Three rules, case-insensitive; the first two also see across a line break, with the comment
leader '#' of the next line:

- `seed`: the internal names of the papers, "seed 001" .. "seed 009" (cite the paper by its
  authors: "Zheng, Ma & Shao 2018"). "seed = 3", "five random seeds", "seed 1" pass.
- `issue`: an issue number, "issue 18", "issues 5 and 20", "issue #35", "the issue (18)".
  (A journal's issue number in a citation would be caught too: write "no. 3" there.)
- `hash`: a commit-like word of 7 to 10 hex digits (at least one digit and one letter a-f, an
  optional trailing '^') inside parentheses or after "of ": "(7a29777)", "runner of 0530a7d",
  "(2 December, 7a29777; ...)". Words inside backticks are not read by this rule. Job keys (12
  hex digits and more) and solver fingerprints (16) are longer and pass; so do numbers.

Usage: no_internal_refs.py [REPO_ROOT] | --self-test. Exit 0 when nothing is found, 1 otherwise
(each finding printed as FILE:LINE: [RULE] MATCH).
"""
import pathlib
import re
import sys

# Whitespace between two words, possibly across one line break and a TOML/CSV comment leader.
SEP = r"(?:[ \t]+|[ \t]*\n[ \t]*(?:#[ \t]*)?)"
HEX = r"(?=[0-9a-f]*[0-9])(?=[0-9a-f]*[a-f])[0-9a-f]{7,10}"
RULES = [
    ("seed", re.compile(r"\bseed" + SEP + r"00[0-9]\b", re.I)),
    ("issue", re.compile(r"\bissues?" + r"(?:[ \t]*|[ \t]*\n[ \t]*(?:#[ \t]*)?)" + r"\(?#?[0-9]+\b", re.I)),
]
HASH_IN_PARENS = re.compile(r"\(([^()]*)\)")
HASH_WORD = re.compile(r"(?<![0-9a-z_\-./])" + HEX + r"\^?(?![0-9a-z_\-])", re.I)
HASH_AFTER_OF = re.compile(r"\bof" + SEP + r"(" + HEX + r")\^?(?![0-9a-z_\-])", re.I)
BACKTICKS = re.compile(r"`[^`\n]*`")


def scannable_text(path, text):
    """The text the rules read: a CSV file's data rows are blanked (line numbers kept)."""
    if path.suffix.lower() == ".csv":
        return "\n".join(l if l.lstrip().startswith("#") else "" for l in text.split("\n"))
    return text


def findings(text):
    """(offset, rule, matched text) of every internal reference in text."""
    out = []
    for name, rx in RULES:
        out += [(m.start(), name, m.group(0)) for m in rx.finditer(text)]
    plain = BACKTICKS.sub(lambda m: " " * len(m.group(0)), text)
    seen = set()
    for m in HASH_IN_PARENS.finditer(plain):
        for w in HASH_WORD.finditer(m.group(1)):
            at = m.start(1) + w.start()
            seen.add(at)
            out.append((at, "hash", w.group(0)))
    for m in HASH_AFTER_OF.finditer(plain):
        if m.start(1) not in seen:
            out.append((m.start(1), "hash", m.group(0)))
    return sorted(out)


def files(root):
    found = [root / "README.md"]
    found += sorted((root / "docs").rglob("*.md"))
    found += sorted((root / "studies").glob("*.toml"))
    found += sorted(p for p in (root / "studies" / "reference").glob("*") if p.is_file())
    return [p for p in found if p.is_file()]


def located(path, text):
    """(line, rule, match) of every internal reference in a file's text."""
    text = scannable_text(path, text)
    return [(text.count("\n", 0, at) + 1, rule, match) for at, rule, match in findings(text)]


def scan(root):
    if not (root / "README.md").is_file():
        print(f"no README.md under {root}: not a repository root")
        return 2
    paths = files(root)
    bad = 0
    for p in paths:
        for line, rule, match in located(p, p.read_text(encoding="utf-8", errors="replace")):
            print(f"{p.relative_to(root)}:{line}: [{rule}] {' '.join(match.split())}")
            bad += 1
    print(f"{len(paths)} files scanned, {bad} internal reference(s) found")
    return 1 if bad else 0


# (text, rules that must be found; empty: the text must pass)
CASES = [
    # seed
    ("as in seed 002, section 4.2", {"seed"}),
    ("Seed 004's Table 1", {"seed"}),
    ("(seed 001 Figs. 9-10)", {"seed"}),
    ("h = 1.3 dx, the seed\n# 002 set-up", {"seed"}),
    ("seed 1 gives 0.189 and the seed mean is in the table", set()),
    ("seed = 3", set()),
    ("five random seeds, mean over seeds 1-5", set()),
    ("seed = [1, 2, 3, 4, 5]", set()),
    ("Zheng, Ma & Shao (2018), Applied Sciences 8, 249", set()),
    # issue
    ("the elastic solid of issue 18", {"issue"}),
    ("## What is not done (issues 5 and 20)", {"issue"}),
    ("### The PPE (issue 21, part 1)", {"issue"}),
    ("see Issue #35", {"issue"}),
    ("the issue (18) asks for it", {"issue"}),
    ("the layer's jump is the only change. Issue\n# 20.", {"issue"}),
    ("tissue 5 is not an issue", set()),
    ("the acceptance check: below 0.05", set()),
    # hash
    ("re-run 3 Dec. (0530a7d)", {"hash"}),
    ("with the runner of 0530a7d, two at a time", {"hash"}),
    ("(2 December, 7a29777; committed in docs/results)", {"hash"}),
    ("before the cached coefficients (db46f90^; above)", {"hash"}),
    ("HEAD (9f33297dc)", {"hash"}),
    ("CPU (runner of\n# 0530a7d, steady by t = 14-18)", {"hash"}),
    ("the job `7a2067397e3b` (the `coarse` tier's job `7a2067397e3b`)", set()),
    ("its fingerprint differs from this build's 3fa81c2e4b1d90aa)", set()),
    ("(code_version `fbc98e4-dirty`)", set()),
    ("(the limit of 1000000 jobs)", set()),
    ("(decade) and (deadbeef)", set()),
    ("(2026-12-02) of 2026120", set()),
    ("a job key (c71cacb7145e) is longer", set()),
]


def self_test():
    failed = 0
    for n, (text, want) in enumerate(CASES):
        got = {rule for _, rule, _ in findings(text)}
        if got != want:
            failed += 1
            print(f"self-test case {n}: {text!r}: expected {sorted(want) or 'nothing'}, "
                  f"found {sorted(got) or 'nothing'}")
    # A CSV file: comment lines are read, data rows are not.
    csv_text = "# Wang, Haidn & Hu, seed 002, Table 2\nsource,value\nseed 002 (present),0.790\n"
    got = [(line, rule) for line, rule, _ in located(pathlib.Path("x.csv"), csv_text)]
    if got != [(1, "seed")]:
        failed += 1
        print(f"self-test csv: expected [(1, 'seed')], found {got}")
    total = len(CASES) + 1
    print(f"{total - failed} passed, {failed} failed")
    return 1 if failed else 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    return scan(root)


if __name__ == "__main__":
    sys.exit(main())
