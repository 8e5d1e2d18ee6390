#!/usr/bin/env python3
"""Citation lint: every reference to a document in the repository must resolve.

Usage: tools/lint_citations.py [--stats] [--root DIR]

Scans every tracked text file (`git ls-files`; skipped: drive/od/tables/, *.png,
package-lock.json, files with a NUL byte) line by line for three kinds of citation:

1. `NAME.md §N[.M…]` — a section citation. NAME may carry a path (`docs/reference/web.md §8.5`).
   A chain that follows it belongs to the same file: `web.md §8.1, §8.2`, `§8.1/§8.10`,
   `§5–§8`, `§6.4–6.6`, `§2 and §3`, `§§2.3–2.4` (both ends of a range are checked). A `§N`
   that does not follow a file name in this way is not checked (it cites the citing file
   itself or a file named earlier in the text). A citation wrapped after the file name — `.md`
   ending one line, `§N` starting the next after an optional comment marker — is joined.
2. `<topic>.md` without `§` — a bare file citation, checked only when TOPIC is one of the
   reference topics below (other bare names such as `README.md` are too ambiguous).
3. `<dir>/<name>.md` without `§` — a file named with a path; checked for existence. Markdown
   link targets `[text](<target>.md)` are checked the same way (their text is not a citation).
   Paths holding a placeholder (`NNNN`, `<`, `>`, `*`, `{`, `}`, `…`) and URLs are ignored.

Resolution:
- a bare reference topic `<topic>.md` names `docs/reference/<topic>.md`; `design.md` names
  `docs/design.md`;
- any other name or path names that file from the repository root, or else relative to the
  citing file's directory. The file must exist in the work tree.
- `§N` must be a Markdown heading of that file whose first token is the number (`## 8.5 I/O`,
  `### 8.5. I/O`, `#### 10.1.8 Availability`).
- Items inside a section: a number P.k that is not a heading still resolves when P is a heading
  and P's own text (up to the next heading) holds an ordered-list item `k.` or `k)`. The sources
  genuinely cite such items (refgo's §15.2 is item 2 of the numbered test list of its §15,
  morse-led's §7.1 item 1 of its §7), so this one level of fallback is allowed; a number whose
  parent section has no such item still fails.

Output: one line per unresolved citation, `file:line: citation — reason`; exit status 1 if any.
`--stats` also prints how often each target file is cited (resolved and unresolved).
"""

from __future__ import annotations

import argparse
import collections
import os
import re
import subprocess
import sys

TOPICS = {
    "refgo", "udp-debug", "morse-led", "models", "persistence", "drive-core", "iofunc",
    "object-dictionary", "slcan-canopen", "web", "scripting", "faulhaber", "design",
}
SKIP_PREFIXES = ("drive/od/tables/",)
SKIP_SUFFIXES = (".png", "package-lock.json")
PLACEHOLDER = re.compile(r"NNNN|[<>*{}…]")

NUM = r"\d+(?:\.\d+)*"
# A .md name, possibly with a path; not preceded by a character that would make it part of a
# longer token (a URL is blanked out before matching).
MD_NAME = r"(?<![\w./-])((?:\.{1,2}/|[\w.-]+/)*[\w.-]+\.md)(?![\w-])"
SECTION = re.compile(
    MD_NAME
    + r"[ \t]*§§?[ \t]?(" + NUM + r")"
    + r"((?:[ \t]*(?:[–—-][ \t]*§?|/[ \t]*§|,[ \t]*§|[ \t]+(?:and|or|&)[ \t]+§)§?[ \t]?" + NUM + r")*)"
)
CHAIN_ITEM = re.compile(r"(" + NUM + r")")
FILE_ONLY = re.compile(MD_NAME)
MD_LINK = re.compile(r"\[[^\]]*\]\(([^)\s#]+\.md)(?:#[^)]*)?\)")
URL = re.compile(r"[A-Za-z][\w+.-]*://\S+")
HEADING = re.compile(r"^ {0,3}#{1,6}[ \t]+(" + NUM + r")\.?(?=[ \t]|$)")
LIST_ITEM = re.compile(r"^[ \t]*(?:\*\*)?(\d+)[.)](?:\*\*)?[ \t]")
ANY_HEADING = re.compile(r"^ {0,3}#{1,6}[ \t]")
FENCE = re.compile(r"^ {0,3}(```|~~~)")
WRAPPED_END = re.compile(r"\.md[ \t]*$")
WRAPPED_NEXT = re.compile(r"^[ \t]*(?://+|#+|\*+|--|;+)?[ \t]*(§.*)$")


class Target:
    """The sections of one Markdown file: heading numbers and the list items under each."""

    def __init__(self, path: str):
        self.headings: set[str] = set()
        self.items: dict[str, set[str]] = collections.defaultdict(set)
        current = None
        in_fence = False
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                if FENCE.match(line):
                    in_fence = not in_fence
                    continue
                if in_fence:
                    continue
                m = HEADING.match(line)
                if m:
                    current = m.group(1)
                    self.headings.add(current)
                    continue
                if ANY_HEADING.match(line):
                    current = None
                    continue
                m = LIST_ITEM.match(line)
                if m and current is not None:
                    self.items[current].add(m.group(1))

    def has(self, number: str) -> bool:
        if number in self.headings:
            return True
        parent, _, last = number.rpartition(".")
        return bool(parent) and parent in self.headings and last in self.items.get(parent, ())


def tracked_files(root: str) -> list[str]:
    out = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True, capture_output=True).stdout
    names = [n.decode("utf-8", "replace") for n in out.split(b"\0") if n]
    return [n for n in names if not n.startswith(SKIP_PREFIXES) and not n.endswith(SKIP_SUFFIXES)]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stats", action="store_true", help="print citation counts per target file")
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    args = ap.parse_args()
    root = os.path.abspath(args.root)

    targets: dict[str, Target | None] = {}

    def load(rel: str) -> Target | None:
        if rel not in targets:
            full = os.path.join(root, rel)
            targets[rel] = Target(full) if os.path.isfile(full) else None
        return targets[rel]

    def resolve(name: str, citing: str, bare_topic_ok: bool) -> tuple[str, bool]:
        """Repository-relative target of a cited name and whether that file exists."""
        if "/" not in name and name[:-3] in TOPICS and bare_topic_ok:
            rel = "docs/design.md" if name == "design.md" else "docs/reference/" + name
            return rel, os.path.isfile(os.path.join(root, rel))
        candidates = [os.path.normpath(name), os.path.normpath(os.path.join(os.path.dirname(citing), name))]
        for rel in candidates:
            if not rel.startswith("..") and os.path.isfile(os.path.join(root, rel)):
                return rel, True
        return candidates[0] if "/" in name else candidates[1], False

    problems: list[str] = []
    stats: dict[str, list[int]] = collections.defaultdict(lambda: [0, 0])  # target: [ok, failed]

    def report(citing: str, lineno: int, cite: str, reason: str, target: str) -> None:
        problems.append(f"{citing}:{lineno}: {cite} — {reason}")
        stats[target][1] += 1

    for citing in tracked_files(root):
        try:
            with open(os.path.join(root, citing), "rb") as f:
                data = f.read()
        except OSError:
            continue  # deleted in the work tree
        if b"\0" in data:
            continue
        lines = data.decode("utf-8", "replace").splitlines()
        for lineno, raw in enumerate(lines, 1):
            if ".md" not in raw:
                continue
            line = URL.sub(lambda m: " " * len(m.group(0)), raw)
            if WRAPPED_END.search(line) and lineno < len(lines):
                # `web.md` at the end of a line, `§6.1 …` at the start of the next one (after a
                # comment marker): one citation, reported at the line of the file name.
                m = WRAPPED_NEXT.match(lines[lineno])
                if m:
                    line = line.rstrip() + " " + m.group(1)
            taken = []  # spans already handled as section citations or link targets
            for m in SECTION.finditer(line):
                taken.append(m.span(1))
                name = m.group(1)
                cite = m.group(0).strip()
                rel, exists = resolve(name, citing, True)
                if not exists:
                    report(citing, lineno, cite, f"{rel} does not exist", rel)
                    continue
                target = load(rel)
                numbers = [m.group(2)] + CHAIN_ITEM.findall(m.group(3))
                missing = [n for n in numbers if not target.has(n)]
                if missing:
                    report(citing, lineno, cite, f"{rel} has no section " + ", ".join("§" + n for n in missing), rel)
                else:
                    stats[rel][0] += 1
            for m in MD_LINK.finditer(line):
                taken.append(m.span(0))  # the link text is not a citation of its own
                name = m.group(1)
                if PLACEHOLDER.search(name):
                    continue
                rel = os.path.normpath(os.path.join(os.path.dirname(citing), name))
                if rel.startswith("..") or not os.path.isfile(os.path.join(root, rel)):
                    report(citing, lineno, f"({name})", f"link target {rel} does not exist", rel)
                else:
                    stats[rel][0] += 1
            for m in FILE_ONLY.finditer(line):
                if any(a <= m.start(1) < b for a, b in taken):
                    continue
                name = m.group(1)
                if PLACEHOLDER.search(name):
                    continue
                if "/" not in name and name[:-3] not in TOPICS:
                    continue  # README.md, CHANGELOG.md …: too ambiguous to check
                rel, exists = resolve(name, citing, True)
                if exists:
                    stats[rel][0] += 1
                else:
                    report(citing, lineno, name, f"{rel} does not exist", rel)

    for p in problems:
        print(p)
    if args.stats:
        width = max((len(t) for t in stats), default=10)
        print(f"\n{'target':<{width}}  resolved  unresolved")
        for t in sorted(stats, key=lambda t: (-sum(stats[t]), t)):
            ok, bad = stats[t]
            print(f"{t:<{width}}  {ok:8}  {bad:10}")
        print(f"{len(problems)} unresolved citation(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
