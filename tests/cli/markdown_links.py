#!/usr/bin/env python3
"""Every relative link and every #anchor in the project's Markdown files resolves.

usage: markdown_links.py [ROOT [FILE.md ...]]

ROOT defaults to the repository root (two folders up). Without FILEs, the Markdown files
tracked by git are checked (every *.md under ROOT outside build/ and hidden folders when git
is not available). A link [text](target) must name an existing file or folder relative to
the file it is in; an anchor (#name, or path.md#name) must be a heading of the target file,
as GitHub writes it: lowercase, punctuation removed, spaces to '-', a repeated heading
suffixed -1, -2, .... Links inside code (fenced blocks or `spans`) and external links
(http:, https:, mailto:) are not checked. Exit status 1 with one line per broken link.
"""
import os
import re
import subprocess
import sys

LINK = re.compile(r"(?<!\!)\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
IMAGE = re.compile(r"!\[[^\]]*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")


def slug(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text only
    text = re.sub(r"<[^>]+>", "", text).strip().lower()
    text = "".join(ch for ch in text if ch.isalnum() or ch in " -_")
    return text.replace(" ", "-")


def prose_lines(text):
    """The lines outside fenced code blocks, with their numbers."""
    fence = None
    for number, line in enumerate(text.split("\n"), 1):
        m = FENCE.match(line)
        if fence is None and m:
            fence = m.group(1)
            continue
        if fence is not None:
            if line.strip().startswith(fence):
                fence = None
            continue
        yield number, line


def anchors(path, cache={}):
    if path not in cache:
        seen, result = {}, set()
        with open(path, encoding="utf-8") as f:
            for _, line in prose_lines(f.read()):
                m = HEADING.match(line)
                if not m:
                    continue
                base = slug(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                result.add(base if n == 0 else f"{base}-{n}")
        for a in re.findall(r"<a\s+(?:name|id)=\"([^\"]+)\"", open(path, encoding="utf-8").read()):
            result.add(a)
        cache[path] = result
    return cache[path]


def markdown_files(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                              "--exclude-standard", "--", "*.md"],
                             check=True, capture_output=True, text=True).stdout
        files = [f for f in out.split("\0") if f]
        if files:
            return [os.path.join(root, f) for f in files]
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for folder, dirs, names in os.walk(root):
        dirs[:] = [d for d in dirs if not d.startswith(".") and not (folder == root and d == "build")]
        files += [os.path.join(folder, n) for n in names if n.endswith(".md")]
    return sorted(files)


def check(path, root):
    errors = []
    with open(path, encoding="utf-8") as f:
        text = f.read()
    for number, line in prose_lines(text):
        line = re.sub(r"(`+).*?\1", "", line)  # inline code
        for m in list(LINK.finditer(line)) + list(IMAGE.finditer(line)):
            target = m.group(1)
            if not target or re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
                continue
            file_part, _, anchor = target.partition("#")
            where = f"{os.path.relpath(path, root)}:{number}: ({target})"
            dest = path if not file_part else os.path.normpath(
                os.path.join(os.path.dirname(path), file_part))
            if not os.path.exists(dest):
                errors.append(f"{where}: no file {os.path.relpath(dest, root)}")
                continue
            if anchor:
                if dest != path and (os.path.isdir(dest) or not dest.endswith(".md")):
                    errors.append(f"{where}: an anchor into something that is not a Markdown file")
                elif anchor not in anchors(dest):
                    errors.append(f"{where}: no heading #{anchor} in {os.path.relpath(dest, root)}")
    return errors


def main(argv):
    root = os.path.abspath(argv[1]) if len(argv) > 1 else \
        os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    files = [os.path.abspath(f) for f in argv[2:]] or markdown_files(root)
    errors = [e for f in files for e in check(f, root)]
    for e in errors:
        print(e)
    if errors:
        print(f"FAIL: {len(errors)} broken link(s) in {len(files)} Markdown files")
        return 1
    print(f"every relative link and anchor resolves in {len(files)} Markdown files")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
