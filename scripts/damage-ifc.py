#!/usr/bin/env python3
"""Writes a deliberately damaged copy of an IFC file this program exported (export/model.ifc), for
checking that `mopad eval --model` sees the damage (scripts/model-eval-acceptance.sh):

  damage-ifc.py IN.ifc OUT.ifc [--move-wall 0.10] [--remove-door]

--move-wall D  moves the first IfcWall (file order) that no opening voids by D metres along its
               body's extrusion axis (the wall's horizontal normal): both its faces move D.
--remove-door  removes the first IfcDoor (file order) with its opening element, the voids and
               fills relations, and every reference to them: the wall is whole there.
Prints what it changed, one line each. Plain STEP text edits; no IFC library needed.
"""
import argparse
import re
import sys

ENTITY = re.compile(r"^#(\d+)\s*=\s*([A-Z0-9_]+)\((.*)\);\s*$")


def parse(text):
    """(header lines, {id: (entity, args)}, order, trailer lines)."""
    lines = text.split("\n")
    start = lines.index("DATA;") + 1
    end = lines.index("ENDSEC;", start)
    ents, order = {}, []
    for line in lines[start:end]:
        m = ENTITY.match(line.strip())
        if not m:
            raise SystemExit("damage-ifc: error: not one entity per line: " + line[:80])
        i = int(m.group(1))
        ents[i] = (m.group(2), m.group(3))
        order.append(i)
    return lines[:start], ents, order, lines[end:]


def refs(args):
    return [int(x) for x in re.findall(r"#(\d+)", args)]


def top_args(args):
    """Top-level comma-separated attributes (strings and parentheses respected)."""
    out, depth, cur, quoted = [], 0, "", False
    for ch in args:
        if ch == "'":
            quoted = not quoted
        if not quoted and ch == "(":
            depth += 1
        elif not quoted and ch == ")":
            depth -= 1
        if ch == "," and depth == 0 and not quoted:
            out.append(cur)
            cur = ""
        else:
            cur += ch
    out.append(cur)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("inp")
    ap.add_argument("out")
    ap.add_argument("--move-wall", type=float, default=None)
    ap.add_argument("--remove-door", action="store_true")
    a = ap.parse_args()
    head, ents, order, tail = parse(open(a.inp, encoding="utf-8").read())
    next_id = max(order) + 1
    gone = set()

    def add(entity, args):
        nonlocal next_id
        ents[next_id] = (entity, args)
        order.append(next_id)
        next_id += 1
        return next_id - 1

    if a.move_wall is not None:
        voided = {refs(top_args(args)[4])[0] for e, args in ents.values() if e == "IFCRELVOIDSELEMENT"}
        wall = next(i for i in order if ents[i][0] == "IFCWALL" and i not in voided)
        wargs = top_args(ents[wall][1])
        shape = refs(wargs[6])[0]  # IfcProductDefinitionShape
        rep = refs(top_args(ents[shape][1])[2])[0]  # IfcShapeRepresentation
        solid = refs(top_args(ents[rep][1])[3])[0]  # IfcExtrudedAreaSolid
        sargs = top_args(ents[solid][1])
        place = refs(sargs[1])[0]  # IfcAxis2Placement3D
        pargs = top_args(ents[place][1])
        loc = [float(x) for x in re.findall(r"[-+0-9.eE]+", ents[refs(pargs[0])[0]][1])]
        axis = [float(x) for x in re.findall(r"[-+0-9.eE]+", ents[refs(pargs[1])[0]][1])]
        moved = [loc[k] + a.move_wall * axis[k] for k in range(3)]
        point = add("IFCCARTESIANPOINT", "(" + ",".join(repr(v) for v in moved) + ")")
        new_place = add("IFCAXIS2PLACEMENT3D", ",".join(["#%d" % point] + pargs[1:]))
        sargs[1] = "#%d" % new_place
        ents[solid] = (ents[solid][0], ",".join(sargs))
        print("moved %s %s by %.3f m along (%.3f, %.3f, %.3f)"
              % ("IfcWall", wargs[2], a.move_wall, axis[0], axis[1], axis[2]))

    if a.remove_door:
        door = next(i for i in order if ents[i][0] == "IFCDOOR")
        gone.add(door)
        for i in order:
            e, args = ents[i]
            if e == "IFCRELFILLSELEMENT" and refs(top_args(args)[5])[0] == door:
                opening = refs(top_args(args)[4])[0]
                gone |= {i, opening}
                for j in order:
                    if ents[j][0] == "IFCRELVOIDSELEMENT" and refs(top_args(ents[j][1])[5])[0] == opening:
                        gone.add(j)
        print("removed IfcDoor %s, its opening element and their relations"
              % top_args(ents[door][1])[2])
        changed = True
        while changed:  # drop references; a relation left without objects goes too
            changed = False
            for i in list(order):
                if i in gone:
                    continue
                e, args = ents[i]
                if not set(refs(args)) & gone:
                    continue
                new = args
                for g in gone:
                    new = re.sub(r"\(#%d\)" % g, "()", new)
                    new = re.sub(r",#%d(?=[,)])" % g, "", new)
                    new = re.sub(r"\(#%d,", "(", new)
                if set(refs(new)) & gone or (e.startswith("IFCREL") and "()" in new):
                    gone.add(i)
                else:
                    ents[i] = (e, new)
                changed = True
    body = ["#%d=%s(%s);" % (i, ents[i][0], ents[i][1]) for i in order if i not in gone]
    open(a.out, "w", encoding="utf-8").write("\n".join(head + body + tail))


if __name__ == "__main__":
    sys.exit(main())
