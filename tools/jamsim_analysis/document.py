"""A small document model written as Markdown and as HTML: headings, paragraphs, tables
(DataFrames) and figures."""
import html

import numpy as np
import pandas as pd


def _cell(v):
    if isinstance(v, (float, np.floating)):
        if not np.isfinite(v):
            return "" if np.isnan(v) else str(v)
        return f"{v:.6g}"
    return str(v)


class Document:
    """Blocks in order: ("h", level, text), ("p", text), ("table", DataFrame), ("img", file, caption)."""

    def __init__(self, title):
        self.title = title
        self.blocks = []

    def heading(self, text, level=2):
        self.blocks.append(("h", level, text))

    def paragraph(self, text):
        self.blocks.append(("p", text))

    def table(self, frame):
        self.blocks.append(("table", pd.DataFrame(frame)))

    def figure(self, filename, caption):
        self.blocks.append(("img", filename, caption))

    def markdown(self):
        out = [f"# {self.title}", ""]
        for b in self.blocks:
            if b[0] == "h":
                out += ["#" * b[1] + " " + b[2], ""]
            elif b[0] == "p":
                out += [b[1], ""]
            elif b[0] == "table":
                t = b[1]
                out.append("| " + " | ".join(map(str, t.columns)) + " |")
                out.append("|" + "---|" * len(t.columns))
                for row in t.itertuples(index=False):
                    out.append("| " + " | ".join(_cell(v).replace("|", "/") for v in row) + " |")
                out.append("")
            else:
                out += [f"![{b[2]}]({b[1]})", "", f"*{b[2]}*", ""]
        return "\n".join(out)

    def html(self):
        out = ["<!DOCTYPE html>", "<html><head><meta charset='utf-8'>",
               f"<title>{html.escape(self.title)}</title>",
               "<style>body{font-family:sans-serif;max-width:1000px;margin:auto}"
               "table{border-collapse:collapse;font-size:small}td,th{border:1px solid #ccc;padding:2px 6px}"
               "img{max-width:100%}</style></head><body>", f"<h1>{html.escape(self.title)}</h1>"]
        for b in self.blocks:
            if b[0] == "h":
                out.append(f"<h{b[1]}>{html.escape(b[2])}</h{b[1]}>")
            elif b[0] == "p":
                out.append(f"<p>{html.escape(b[1])}</p>")
            elif b[0] == "table":
                t = b[1]
                head = "".join(f"<th>{html.escape(str(c))}</th>" for c in t.columns)
                rows = "".join("<tr>" + "".join(f"<td>{html.escape(_cell(v))}</td>" for v in r) + "</tr>"
                               for r in t.itertuples(index=False))
                out.append(f"<table><tr>{head}</tr>{rows}</table>")
            else:
                out.append(f"<figure><img src='{html.escape(b[1])}' alt='{html.escape(b[2])}'>"
                           f"<figcaption>{html.escape(b[2])}</figcaption></figure>")
        out.append("</body></html>")
        return "\n".join(out)
