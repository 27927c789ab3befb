#!/usr/bin/python3
"""Checks the relative links of README.md and docs/*.md: every target file must exist, and a
#fragment must name a heading of the target Markdown file (GitHub's anchor rule).

  /usr/bin/python3 tools/check_links.py      (exit 1 and one line per broken link)
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def anchors(path):
    """GitHub's heading anchors: lower case, punctuation dropped, spaces to '-'."""
    out, seen = set(), {}
    in_code = False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            in_code = not in_code
        if in_code or not line.startswith("#"):
            continue
        text = line.lstrip("#").strip()
        a = re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")
        n = seen.get(a, 0)
        seen[a] = n + 1
        out.add(a if n == 0 else f"{a}-{n}")
    return out


def main():
    files = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
    bad = 0
    for f in files:
        text = re.sub(r"```.*?```", "", f.read_text(encoding="utf-8"), flags=re.S)
        for target in LINK.findall(text):
            if re.match(r"^[a-z]+:", target):
                continue  # http:, https:, mailto:
            path, _, frag = target.partition("#")
            dest = (f.parent / path).resolve() if path else f
            if not dest.exists():
                print(f"{f.relative_to(ROOT)}: {target}: no such file")
                bad += 1
            elif frag and dest.suffix == ".md" and frag not in anchors(dest):
                print(f"{f.relative_to(ROOT)}: {target}: no heading '#{frag}' in {path or f.name}")
                bad += 1
    print(f"{len(files)} files checked, {bad} broken links")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
