"""keys.py - the key table of docs/scene-format.md against the definition rows.

The rows of src/fields.h (rj__link_fields, rj__joint_fields, rj__solver_fields,
rj__load_fields) are what the parser takes; the material's and section's keys are
the link's that RJ__SK_MAT_KEYS and RJ__SK_SEC_KEYS name (src/scene_parse.h). For
each section:
- every key the rows give has a line in the table, and every key the table names is
  one the rows give;
- each key's unit (a number's) is on one of its lines ("angle" and "rate" say rad and
  rad/s; "as above" refers to the material's and section's lines);
- each key's default is among the numbers of the default cell of one of its lines
  (an angle may be written in deg; "none" is a default of 0, a member unset).
One PASS or FAIL line per section and check.
Run from the repository root: python3 tests/keys.py
"""
import math
import re
import sys

FIELDS = "src/fields.h"
PARSER = "src/scene_parse.h"
DOC = "docs/scene-format.md"
TABLES = {"link": "rj__link_fields", "joint": "rj__joint_fields",
          "solver": "rj__solver_fields", "load": "rj__load_fields",
          "actuator": "rj__actuator_fields", "coupling": "rj__coupling_fields"}
COUNTS = {"link": "RJ__LK_", "joint": "RJ__JK_", "solver": "RJ__VK_", "load": "RJ__AK_",
          "actuator": "RJ__CK_", "coupling": "RJ__PK_"}


def split_args(body):
    """The top-level comma-separated arguments of a macro call's body."""
    args, depth, cur, quoted = [], 0, "", False
    for ch in body:
        if ch == '"':
            quoted = not quoted
        if not quoted and ch in "([{":
            depth += 1
        if not quoted and ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0 and not quoted:
            args.append(cur.strip())
            cur = ""
        else:
            cur += ch
    args.append(cur.strip())
    return args


def calls(text):
    """(macro, args) for each RJ__F / RJ__FC / RJ__FE / RJ__FA / RJ__FPART row or brace
    row { "key", ... } in text, in order."""
    out, i = [], 0
    pat = re.compile(r"\b(RJ__FPART|RJ__FE|RJ__FA|RJ__FC|RJ__F)\(|(\{) \"")
    while True:
        m = pat.search(text, i)
        if not m:
            return out
        brace = m.group(2) is not None
        start = m.start(2) + 1 if brace else m.end()
        opens, closes = ("{", "}") if brace else ("(", ")")
        j, depth, quoted = start, 1, False
        while depth:
            if text[j] == '"':
                quoted = not quoted
            elif not quoted:
                depth += {opens: 1, closes: -1}.get(text[j], 0)
            j += 1
        out.append(("BRACE" if brace else m.group(1), split_args(text[start:j - 1])))
        i = j


def value(expr):
    """A default's C expression as a number."""
    expr = expr.replace("RJ__PI", repr(math.pi)).replace("RJ_METHOD_ADAPTIVE", "1")
    expr = expr.replace("RJ_RELEASE_RC13", "1").replace("RJ_IN_PLACE_AUTO", "0")
    expr = expr.replace("RJ_ACTUATOR_TORQUE", "0")
    return float(eval(expr, {"__builtins__": {}}))


def rows_of(text, name):
    """[(key, unit, default, numeric)] of table name, in order."""
    start = text.find("static const rj__field " + name)
    if start < 0:
        sys.exit("keys.py: no table %s in %s" % (name, FIELDS))
    body = text[start:text.index("};", start)]
    rows = []
    for macro, a in calls(body):
        key = a[0].strip('"')
        if macro == "RJ__FPART":
            rows.append((key, "", None, False))
        elif macro == "RJ__FE":
            rows.append((key, "", None, False))
        elif macro == "BRACE":
            numeric = a[5] in ("RJ__FT_REAL", "RJ__FT_ANGLE", "RJ__FT_RATE")
            rows.append((key, a[2].strip('"'), value(a[12]), numeric))
        elif macro == "RJ__FC":
            rows.append((key, a[2].strip('"'), value(a[8]), True))
        elif macro == "RJ__FA":
            numeric = a[3] in ("RJ__FT_REAL", "RJ__FT_ANGLE", "RJ__FT_RATE")
            rows.append((key, a[2].strip('"'), value(a[10]), numeric))
        else:
            numeric = a[3] in ("RJ__FT_REAL", "RJ__FT_ANGLE", "RJ__FT_RATE", "RJ__FT_INT",
                               "RJ__FT_VEC2")
            rows.append((key, a[2].strip('"'), value(a[9]), numeric))
    return rows


def key_count(text, prefix):
    """The number of keys of a kind: its enum's members before PREFIX N."""
    m = re.search(r"enum \{\s*(" + prefix + r"\w+.*?)" + prefix + r"N,", text, re.S)
    return len(re.findall(prefix + r"\w+", m.group(1)))


def link_subset(src, macro, link_keys):
    """The link keys a RJ__SK_*_KEYS bit mask names."""
    start = src.find("#define " + macro)
    if start < 0:
        sys.exit("keys.py: no macro %s in %s" % (macro, PARSER))
    body = []
    for line in src[start:].splitlines():
        body.append(line)
        if not line.rstrip().endswith("\\"):
            break
    names = [k.upper() for k in link_keys]
    found = re.findall(r"RJ__LK_(\w+)", " ".join(body))
    return {link_keys[names.index(n)] for n in found}


def doc_table(text):
    """{section: [(keys, value and later cells, default cell)]} from the table whose header is
    | section | key | ..."""
    rows, section, on = {}, None, False
    for line in text.splitlines():
        if line.startswith("| section | key |"):
            on = True
            continue
        if not on:
            continue
        if not line.startswith("|"):
            if rows:
                break
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 4 or cells[0].startswith("---"):
            continue
        if cells[0]:
            section = cells[0]
        keys = re.findall(r"`([A-Za-z_0-9]+)`", cells[1])
        rows.setdefault(section, []).append((keys, " | ".join(cells[2:]), cells[3]))
    return rows


def numbers(cell):
    """The numbers a default cell gives, angles in deg as rad."""
    out = []
    for code in re.findall(r"`([^`]*)`", cell):
        for num, deg in re.findall(r"(-?[0-9.]+(?:e-?[0-9]+)?)( deg)?", code):
            try:
                v = float(num)
            except ValueError:
                continue
            out.append(math.radians(v) if deg else v)
    return out


def check_section(section, rows, lines):
    """PASS/FAIL lines for one section: keys, units, defaults."""
    keys = {r[0] for r in rows}
    have = {k for ks, _, _ in lines for k in ks}
    out = []
    missing, extra = sorted(keys - have), sorted(have - keys)
    if missing or extra:
        out.append("FAIL keys: %s: %s's table lacks %s and names %s, which the rows do not "
                   "give" % (section, DOC, missing or "none", extra or "none"))
    else:
        out.append("PASS keys: %s: the %d keys of %s's table are the rows'" %
                   (section, len(keys), DOC))
    bad_unit, bad_default = [], []
    for key, unit, default, numeric in rows:
        mine = [(v, d) for ks, v, d in lines if key in ks]
        if not mine or not numeric:
            continue
        words = {"rad": ("rad", "angle"), "rad/s": ("rad/s", "rate")}.get(unit, (unit,))
        if unit and not any(w in v for v, _ in mine for w in words + ("as above",)):
            bad_unit.append("%s (%s)" % (key, unit))
        if default is not None and not any(
                any(abs(x - default) <= 1e-9 * max(1.0, abs(default)) for x in numbers(d))
                or "as above" in d or (default == 0 and d.startswith("none"))
                for _, d in mine):
            bad_default.append("%s (%g)" % (key, default))
    for what, bad in (("units", bad_unit), ("defaults", bad_default)):
        if bad:
            out.append("FAIL keys: %s: the %s of %s are not in %s's table" %
                       (section, what, ", ".join(bad), DOC))
        else:
            out.append("PASS keys: %s: every number's %s in %s's table is the rows'" %
                       (section, what[:-1], DOC))
    return out


def main():
    text = open(FIELDS).read()
    src = open(PARSER).read()
    doc = doc_table(open(DOC).read())
    want = {}
    for section, table in TABLES.items():
        rows = rows_of(text, table)
        want[section] = rows[:key_count(text, COUNTS[section])]
    link_keys = [r[0] for r in want["link"]]
    for sub, macro in (("material", "RJ__SK_MAT_KEYS"), ("section", "RJ__SK_SEC_KEYS")):
        keep = link_subset(src, macro, link_keys)
        want[sub] = [r for r in want["link"] if r[0] in keep]
    failed = 0
    for section, rows in want.items():
        for line in check_section(section, rows, doc.get(section, [])):
            print(line)
            failed += line.startswith("FAIL")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
