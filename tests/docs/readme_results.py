#!/usr/bin/env python3
"""Every number the documentation's result tables quote equals a committed run.

The tables are read from README.md and from every Markdown page under docs/ (the results live in
docs/results.md); a page without a results mark is skipped.

The runs behind these tables are committed as docs/results/<study>.csv, written by
`runner publish STUDY`, with exactly the header `study,job,tier,code_version,params,metric,value`
(one row per job and metric; `params` is the job's canonical JSON, `job` its key).

A result table is marked by a comment on the line before it:

    <!-- results: isph_cavity isph_cavity_re100 -->
    | Re | dx | form | u_x min <!-- ux_min --> | CPU/step <!-- ms_per_step*1000 --> |
    |---|---|---|---|---|
    | 1000 <!-- job: Re=1000 dx=0.02 visc=visc04 --> | 0.02 | VISC-04 | -0.3531 (-0.3829) | 15.8 ms |

- A header cell that ends in `<!-- METRIC -->` (optionally `METRIC*FACTOR`) names the metric of
  its column; columns without one (parameters, labels, references) are not checked.
- A row whose first cell holds `<!-- job: KEY=VALUE ... -->` is a run of ours: the KEY=VALUE pairs
  (parameters of the job's canonical JSON, or `tier=NAME`, `study=NAME`; `!KEY`: jobs whose
  canonical JSON lacks KEY, a parameter left at its neutral default) must select exactly one
  job of the table's studies, and each of its cells in a metric column must equal that job's
  metric to the digits quoted: the first number of the cell (bold and backticks stripped; what
  follows it, a unit or a reference in parentheses, is not read) is the value rounded, so
  |quoted - recorded * FACTOR| <= half a unit of its last digit. An empty cell is not checked; a
  non-empty cell without a leading number fails (text goes into a column without a metric).
- Rows without a job comment (the paper's values, other codes) are references and not checked.
- A marked table with no checked row fails, and so does a results file with another header.

Usage: readme_results.py [REPO_ROOT] | --self-test. Exit 0 when every check holds, 1 otherwise; the last line
is 'N passed, N failed' over the checked cells.
"""
import csv
import json
import math
import pathlib
import re
import sys

HEADER = ["study", "job", "tier", "code_version", "params", "metric", "value"]
MARK = re.compile(r"^<!--\s*results:\s*(.*?)\s*-->\s*$")
COMMENT = re.compile(r"<!--\s*(.*?)\s*-->")
NUMBER = re.compile(r"^[-+]?(\d+)(?:\.(\d+))?(?:[eE]([-+]?\d+))?")


def load_results(root, study, cache):
    if study not in cache:
        path = root / "docs" / "results" / (study + ".csv")
        if not path.exists():
            raise ValueError(f"no committed runs of study '{study}': {path} is missing "
                             f"(runner publish {study})")
        jobs = {}
        with open(path, newline="") as f:
            rows = csv.reader(f)
            if next(rows, None) != HEADER:
                raise ValueError(f"{path}: line 1 is not the header {','.join(HEADER)}")
            for n, r in enumerate(rows, start=2):
                if len(r) != 7 or r[0] != study:
                    raise ValueError(f"{path}: line {n}: expected 7 fields of study '{study}'")
                job = jobs.setdefault(r[1], {"study": study, "tiers": r[2].split(";"),
                                             "params": json.loads(r[4]), "metrics": {}})
                job["metrics"][r[5]] = float(r[6])
        cache[study] = jobs
    return cache[study]


def value_matches(want, have):
    if isinstance(have, bool) or isinstance(have, str):
        return str(have).lower() == want.lower()
    try:
        return math.isclose(float(want), float(have), rel_tol=1e-12, abs_tol=1e-15)
    except ValueError:
        return False


def select(jobs, selector):
    out = []
    for key, job in jobs.items():
        ok = True
        for k, v in selector.items():
            if k == "tier":
                ok = v in job["tiers"]
            elif k == "study":
                ok = job["study"] == v
            elif k.startswith("!"):  # !KEY: the job's identity lacks KEY (at its neutral default)
                ok = k[1:] not in job["params"]
            else:
                ok = k in job["params"] and value_matches(v, job["params"][k])
            if not ok:
                break
        if ok:
            out.append((key, job))
    return out


def cells_of(line):
    s = line.strip()
    if s.startswith("|"):
        s = s[1:]
    if s.endswith("|"):
        s = s[:-1]
    return [c.strip() for c in s.split("|")]


def quoted_number(cell):
    """(value, half a unit of its last digit) of the cell's leading number, or None."""
    text = COMMENT.sub("", cell).replace("**", "").replace("`", "").strip()
    m = NUMBER.match(text)
    if not m:
        return None
    decimals = len(m.group(2) or "")
    exponent = int(m.group(3) or 0)
    return float(m.group(0)), 0.5 * 10.0 ** (exponent - decimals)


def pages(root):
    """README.md and every Markdown page under docs/, in a fixed order."""
    out = [root / "README.md"] if (root / "README.md").exists() else []
    return out + sorted((root / "docs").rglob("*.md"))


def check(root):
    passed, failed, messages = 0, 0, []
    cache = {}
    for page in pages(root):
        p, f, m = check_page(root, page, cache)
        passed, failed = passed + p, failed + f
        messages += m
    # Every committed results file has the exact header.
    for path in sorted((root / "docs" / "results").glob("*.csv")):
        try:
            load_results(root, path.stem, cache)
        except ValueError as e:
            messages.append(str(e))
            failed += 1
    return passed, failed, messages


def check_page(root, page, cache):
    """The checked cells of one Markdown page: (passed, failed, messages)."""
    page_name = page.relative_to(root).as_posix()
    readme = page.read_text().splitlines()
    passed, failed, messages = 0, 0, []
    i = 0
    while i < len(readme):
        mark = MARK.match(readme[i].strip())
        i += 1
        if not mark:
            continue
        where = f"{page_name}:{i}"
        studies = mark.group(1).split()
        while i < len(readme) and not readme[i].strip():
            i += 1
        if i >= len(readme) or not readme[i].lstrip().startswith("|"):
            messages.append(f"{where}: a results mark not followed by a table")
            failed += 1
            continue
        header = cells_of(readme[i])
        columns = {}
        for c, text in enumerate(header):
            m = COMMENT.search(text)
            if m:
                name, _, factor = m.group(1).partition("*")
                columns[c] = (name.strip(), float(factor) if factor else 1.0, text)
        i += 2  # the header and its |---| line
        checked_rows = 0
        while i < len(readme) and readme[i].lstrip().startswith("|"):
            line_no, cells = i + 1, cells_of(readme[i])
            i += 1
            m = re.search(r"<!--\s*job:\s*(.*?)\s*-->", cells[0])
            if not m:
                continue
            checked_rows += 1
            selector = dict(kv.split("=", 1) if "=" in kv else (kv, "") for kv in m.group(1).split())
            try:
                jobs = {}
                for s in studies:
                    jobs.update(load_results(root, s, cache))
            except ValueError as e:
                messages.append(f"{page_name}:{line_no}: {e}")
                failed += 1
                continue
            found = select(jobs, selector)
            if len(found) != 1:
                messages.append(f"{page_name}:{line_no}: {m.group(1)} selects {len(found)} jobs of "
                                f"{' '.join(studies)}, not one")
                failed += 1
                continue
            key, job = found[0]
            for c, (metric, factor, title) in columns.items():
                cell = cells[c] if c < len(cells) else ""
                if not COMMENT.sub("", cell).strip():
                    continue
                q = quoted_number(cell)
                title_text = COMMENT.sub("", title).strip()
                if q is None:
                    messages.append(f"{page_name}:{line_no}: column '{title_text}': '{cell}' has no "
                                    f"leading number")
                    failed += 1
                elif metric not in job["metrics"]:
                    messages.append(f"{page_name}:{line_no}: job {key[:12]} has no metric "
                                    f"'{metric}'")
                    failed += 1
                else:
                    have = job["metrics"][metric] * factor
                    if abs(have - q[0]) <= q[1] * (1 + 1e-9):
                        passed += 1
                    else:
                        messages.append(f"{page_name}:{line_no}: column '{title_text}': quoted "
                                        f"{cell!r}, the run ({job['study']} job {key[:12]}) "
                                        f"recorded {metric} = {have:.6g}")
                        failed += 1
        if checked_rows == 0:
            messages.append(f"{where}: a results table without a row of ours (<!-- job: ... -->)")
            failed += 1
    return passed, failed, messages


def self_test():
    """The checker on made-up pages: it must pass the right numbers and fail each wrong one.

    Each case is (README text, results CSV, expected outcome[, page]): the table goes into README.md,
    or into the page named (a docs/ page, as docs/results.md holds the real tables)."""
    import tempfile
    good = """<!-- results: demo -->
| n | err <!-- err --> | time <!-- cpu_s*1000 --> | ref |
|---|---|---|---|
| 20 <!-- job: n_side=20 kind=a --> | **9.19e-03** (1e-6) | 12 ms | 1.0 |
| paper | 1.0 | | |
"""
    csv_text = ("study,job,tier,code_version,params,metric,value\n"
                'demo,k1,quick,v,"{""n_side"":20,""kind"":""a""}",err,0.0091873\n'
                'demo,k1,quick,v,"{""n_side"":20,""kind"":""a""}",cpu_s,0.01204\n'
                'demo,k2,quick,v,"{""n_side"":40,""kind"":""a""}",err,0.5\n')
    cases = [(good, csv_text, True),
             (good.replace("9.19e-03", "9.20e-03"), csv_text, False),  # last digit off
             (good.replace("12 ms", "13 ms"), csv_text, False),  # factor applied
             (good.replace("n_side=20 kind=a", "kind=a"), csv_text, False),  # two jobs match
             (good.replace("**9.19e-03**", "about 9e-3"), csv_text, False),  # text in a metric col
             (good.replace("<!-- err -->", "<!-- err_l2 -->"), csv_text, False),  # no such metric
             (good.replace("<!-- job: n_side=20 kind=a -->", ""), csv_text, False),  # no row
             (good, csv_text.replace("study,job", "study,key"), False),  # header
             (good, csv_text, True, "docs/results.md"),  # the same table on a docs page
             (good.replace("9.19e-03", "9.20e-03"), csv_text, False, "docs/results.md"),
             (good.replace("12 ms", "13 ms"), csv_text, False, "docs/fam/page.md"),  # nested page
             # !KEY selects the job without KEY (k3) apart from the one with it (k1)
             (good.replace("kind=a -->", "!kind -->").replace("**9.19e-03**", "0.25"),
              csv_text + 'demo,k3,quick,v,"{""n_side"":20}",err,0.25\n'
                         'demo,k3,quick,v,"{""n_side"":20}",cpu_s,0.012\n', True),
             (good.replace("kind=a -->", "!kind -->"),  # k3's err is 0.25, not k1's 9.19e-3
              csv_text + 'demo,k3,quick,v,"{""n_side"":20}",err,0.25\n'
                         'demo,k3,quick,v,"{""n_side"":20}",cpu_s,0.012\n', False)]
    ok = True
    for n, (readme, results, expect, *where) in enumerate(cases):
        with tempfile.TemporaryDirectory() as d:
            root = pathlib.Path(d)
            (root / "docs" / "results").mkdir(parents=True)
            page = root / (where[0] if where else "README.md")
            page.parent.mkdir(parents=True, exist_ok=True)
            page.write_text(readme)
            (root / "docs" / "results" / "demo.csv").write_text(results)
            passed, failed, messages = check(root)
            got = failed == 0 and passed > 0
            if got != expect:
                ok = False
                print(f"self-test case {n}: expected {'pass' if expect else 'fail'}, got "
                      f"{passed} passed, {failed} failed: {messages}")
    print(f"{len(cases) if ok else 0} passed, {0 if ok else 1} failed")
    return 0 if ok else 1


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    passed, failed, messages = check(root)
    for m in messages:
        print(m)
    print(f"{passed} passed, {failed} failed")
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
