"""Reading the canonical runner's JSON (conformance/canonical.cpp, --json): the helpers that
conformance_report.py and seed_study.py share.

A file is {"entries": [{"problem", "depth", "depth_unit", "quantity", "value", "se",
"reference", "spread", "relative_error", "scored_error", "scored", "pass", "blocked", "source"}, ...],
"seconds"} ("blocked": why an entry waits for the specification; "source": the light source of a
run reported beside the scored one; both empty otherwise);
a non-finite number is written as null.
"""
import math
from xml.sax.saxutils import escape


def number(x):
    """A JSON number as a float (null, from a non-finite value, as nan)."""
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def entry_key(e):
    """(problem, depth, quantity): numeric depths as floats (1 and 1.0 alike), others as text. A
    run reported beside a problem's scored one under another light source (its "source", e.g.
    problem 4 under a parametric sky) is a problem of its own, "4/gc-sky"."""
    d = number(e.get("depth"))
    problem = str(e.get("problem")) + (f"/{e['source']}" if e.get("source") else "")
    return (problem, d if not math.isnan(d) else str(e.get("depth")), str(e.get("quantity")))


def depth_label(e):
    """"tau 5" for an optical depth, "25 m" for metres, the bare depth without a unit."""
    depth, unit = e.get("depth"), e.get("depth_unit") or ""
    d = number(depth)
    text = f"{d:g}" if not math.isnan(d) else str(depth)
    return f"tau {text}" if unit == "tau" else f"{text} {unit}".strip()


def percent(v, signed, digits=2):
    """A fraction in percent ("-" where it is not finite)."""
    if math.isnan(v) or math.isinf(v):
        return "-"
    return f"{100 * v:+.{digits}f}%" if signed else f"{100 * v:.{digits}f}%"


def cell(text):
    """Text for a markdown table cell."""
    return escape(str(text)).replace("|", "\\|")
