"""CalculiX input decks and output parsing for tests/test_calculix.py (units mm, t, s: MPa, N;
:func:`two_blocks` also in SI, for the unit guards).

Two blocks of linear C3D8 elements: a 20 x 20 x 5 mm base (fixed at its bottom) and a
10 x 10 x 5 mm block on it, pressed by a pressure on its top face and moved sideways by a prescribed
displacement of its top face. The block's bottom face is the slave surface of node-to-surface
penalty contact; its nodes carry the contact areas of :func:`slave_areas`. And :func:`ring`, the
axisymmetric ring compression of ``fe-demo ring``; :func:`billet`, an axisymmetric upsetting.
"""

import re
from pathlib import Path

import numpy as np

__all__ = [
    "two_blocks",
    "two_zones",
    "slave_areas",
    "read_dat",
    "read_blocks",
    "ring",
    "billet",
    "SLAVE0",
    "SLAVE1",
]

#: first node number of the block (its bottom layer is the slave surface)
SLAVE0 = 1001
#: first node number of :func:`two_zones`' second block
SLAVE1 = 2001


def _block(origin, size, divisions, n0, e0):
    axes = [np.linspace(o, o + s, d + 1) for o, s, d in zip(origin, size, divisions, strict=True)]
    nx, ny, nz = divisions
    ids = np.arange((nx + 1) * (ny + 1) * (nz + 1)).reshape(nz + 1, ny + 1, nx + 1) + n0
    nodes = {}
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                nodes[int(ids[k, j, i])] = (axes[0][i], axes[1][j], axes[2][k])
    elements = {}
    e = e0
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                c = ids[k : k + 2, j : j + 2, i : i + 2]
                conn = [c[0, 0, 0], c[0, 0, 1], c[0, 1, 1], c[0, 1, 0]]
                conn += [c[1, 0, 0], c[1, 0, 1], c[1, 1, 1], c[1, 1, 0]]
                elements[e] = (k, [int(v) for v in conn])
                e += 1
    return nodes, elements, ids


def _contact(interaction, contact, slope, tension):
    """The interaction with its linear pressure-overclosure law (``slope``, ``tension`` in the
    deck's units), the contact pair of SSLAVE on SMASTER and the fixed bottom NBASE."""
    name = interaction[0].split("NAME=")[1].strip()
    return [
        *interaction,
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
        f"{slope:g}, {tension:g}",
        f"*CONTACT PAIR, INTERACTION={name}, TYPE={contact}",
        "SSLAVE, SMASTER",
        "*BOUNDARY",
        "NBASE, 1, 3, 0.",
    ]


def two_blocks(
    steps,
    interaction,
    *,
    n=3,
    slope=1e6,
    contact="NODE TO SURFACE",
    contact_print=("CSTR",),
    contact_file=(),
    amplitudes=None,
    si=False,
):
    """The deck's text.

    Parameters
    ----------
    steps : list of (pressure_MPa, ux_mm) or (pressure_MPa, ux_mm, options)
        Values at the end of each static step (ramped from the previous step's). ``options``:
        ``amplitude`` (the name of an entry of ``amplitudes`` the step's pressure follows, as
        ``pressure * a(t)``), ``static`` (the ``*STATIC`` line, default ``0.1, 1.0, 1e-5,
        0.25``), ``uz`` (a prescribed vertical displacement of the top, mm; it stays prescribed
        in the later steps).
    interaction : list of str
        Lines after ``*SURFACE INTERACTION, NAME=...`` (its first line included), e.g. the
        docs' ``*SURFACE INTERACTION, NAME=SBMF`` / ``*FRICTION, USER, DEPVAR=3``; a
        ``*SURFACE BEHAVIOR`` with a linear pressure-overclosure of ``slope`` MPa/mm is appended.
    n : int
        Elements along each side of the block's contact face.
    contact : {"NODE TO SURFACE", "SURFACE TO SURFACE"}
        The ``*CONTACT PAIR``'s ``TYPE``.
    contact_print, contact_file : sequence of str
        Keys of ``*CONTACT PRINT`` and ``*CONTACT FILE`` in every step.
    amplitudes : dict, optional
        ``{name: [(t, a), ...]}``, written as ``*AMPLITUDE`` cards (step time).
    si : bool
        The same deck in SI (m, Pa): lengths times 1e-3, stresses times 1e6 (the arguments stay
        in mm and MPa).
    """
    ln, st = (1e-3, 1e6) if si else (1.0, 1.0)
    nb, eb, ib = _block((0, 0, -5 * ln), (20 * ln, 20 * ln, 5 * ln), (4, 4, 1), 1, 1)
    nt, et, it = _block((5 * ln, 5 * ln, 0), (10 * ln, 10 * ln, 5 * ln), (n, n, 2), SLAVE0, 1001)
    out = ["*HEADING", "two blocks: press, slide, unload, reload", "*NODE"]
    for nodes in (nb, nt):
        out += [f"{k}, {x:.10g}, {y:.10g}, {z:.10g}" for k, (x, y, z) in nodes.items()]
    for elset, els in (("EBASE", eb), ("EBLOCK", et)):
        out.append(f"*ELEMENT, TYPE=C3D8, ELSET={elset}")
        out += [f"{e}, " + ", ".join(map(str, c)) for e, (_, c) in els.items()]
    # C3D8 faces: S1 = nodes 1-2-3-4 (z-), S2 = nodes 5-6-7-8 (z+)
    out.append("*SURFACE, NAME=SMASTER")
    out += [f"{e}, S2" for e, (k, _) in eb.items() if k == 0]
    out.append("*SURFACE, NAME=SSLAVE")
    out += [f"{e}, S1" for e, (k, _) in et.items() if k == 0]
    out.append("*NSET, NSET=NBASE")
    out += [f"{v}," for v in ib[0].ravel()]
    out.append("*NSET, NSET=NTOP")
    out += [f"{v}," for v in it[-1].ravel()]
    for amp, points in (amplitudes or {}).items():
        out.append(f"*AMPLITUDE, NAME={amp}")
        out += [f"{t:.10g}, {a:.10g}" for t, a in points]
    out += [
        "*MATERIAL, NAME=STEEL",
        "*ELASTIC",
        f"{210000.0 * st:.10g}, 0.3",
        "*SOLID SECTION, ELSET=EBASE, MATERIAL=STEEL",
        "*SOLID SECTION, ELSET=EBLOCK, MATERIAL=STEEL",
        *_contact(interaction, contact, slope * st / ln, 0.01 * st),
    ]
    top = [e for e, (k, _) in et.items() if k == 1]
    for step in steps:
        p, ux = step[:2]
        opts = step[2] if len(step) > 2 else {}
        static = opts.get("static", "0.1, 1.0, 1e-5, 0.25")
        out += ["*STEP, INC=200", "*STATIC", static, "*BOUNDARY"]
        out += [f"NTOP, 1, 1, {ux * ln:.10g}", "NTOP, 2, 2, 0."]
        if "uz" in opts:
            out.append(f"NTOP, 3, 3, {opts['uz'] * ln:.10g}")
        out.append(f"*DLOAD, AMPLITUDE={opts['amplitude']}" if "amplitude" in opts else "*DLOAD")
        out += [f"{e}, P2, {p * st:.10g}" for e in top]
        out += ["*NODE PRINT, NSET=NTOP", "RF", "*CONTACT PRINT", ", ".join(contact_print)]
        if contact_file:
            out += ["*CONTACT FILE", ", ".join(contact_file)]
        out.append("*END STEP")
    return "\n".join(out) + "\n"


def two_zones(steps, interactions, *, slope=1e6):
    """Two blocks side by side on one base, each its own contact pair and interaction (mm, MPa).

    Two tool zones (issue 42): the 10 x 10 x 5 mm blocks of :func:`two_blocks` at x = 2..12 and
    18..28 mm on a 30 x 20 x 5 mm base, each bottom face the slave surface of a node-to-surface
    contact pair with the base's top, the first with interaction ``interactions[0]``, the second
    with ``interactions[1]`` (each a list of lines from its ``*SURFACE INTERACTION, NAME=...``,
    as in :func:`two_blocks`). Both tops are pressed and moved alike (``steps`` as there); slave
    nodes from :data:`SLAVE0` and :data:`SLAVE1`, their areas :func:`slave_areas`.
    """
    nb, eb, ib = _block((0, 0, -5), (30, 20, 5), (6, 4, 1), 1, 1)
    blocks = [
        _block((x0, 5, 0), (10, 10, 5), (3, 3, 2), n0, e0)
        for x0, n0, e0 in ((2, SLAVE0, 1001), (18, SLAVE1, 2001))
    ]
    out = ["*HEADING", "two zones: two blocks, two contact pairs", "*NODE"]
    for nodes in (nb, *(b[0] for b in blocks)):
        out += [f"{k}, {x:.10g}, {y:.10g}, {z:.10g}" for k, (x, y, z) in nodes.items()]
    for elset, els in (("EBASE", eb), ("EBLOCKA", blocks[0][1]), ("EBLOCKB", blocks[1][1])):
        out.append(f"*ELEMENT, TYPE=C3D8, ELSET={elset}")
        out += [f"{e}, " + ", ".join(map(str, c)) for e, (_, c) in els.items()]
    out.append("*SURFACE, NAME=SMASTER")
    out += [f"{e}, S2" for e, (k, _) in eb.items() if k == 0]
    out.append("*NSET, NSET=NBASE")
    out += [f"{v}," for v in ib[0].ravel()]
    out.append("*NSET, NSET=NTOP")
    for _, _, ids in blocks:
        out += [f"{v}," for v in ids[-1].ravel()]
    for tag, (_, els, _) in zip("AB", blocks, strict=True):
        out.append(f"*SURFACE, NAME=SSLAVE{tag}")
        out += [f"{e}, S1" for e, (k, _) in els.items() if k == 0]
    out += [
        "*MATERIAL, NAME=STEEL",
        "*ELASTIC",
        "210000., 0.3",
        "*SOLID SECTION, ELSET=EBASE, MATERIAL=STEEL",
        "*SOLID SECTION, ELSET=EBLOCKA, MATERIAL=STEEL",
        "*SOLID SECTION, ELSET=EBLOCKB, MATERIAL=STEEL",
    ]
    for tag, inter in zip("AB", interactions, strict=True):
        name = inter[0].split("NAME=")[1].strip()
        out += [
            *inter,
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{slope:g}, 0.01",
            f"*CONTACT PAIR, INTERACTION={name}, TYPE=NODE TO SURFACE",
            f"SSLAVE{tag}, SMASTER",
        ]
    out += ["*BOUNDARY", "NBASE, 1, 3, 0."]
    top = [e for b in blocks for e, (k, _) in b[1].items() if k == 1]
    for p, ux in steps:
        out += ["*STEP, INC=200", "*STATIC", "0.1, 1.0, 1e-5, 0.25", "*BOUNDARY"]
        out += [f"NTOP, 1, 1, {ux:.10g}", "NTOP, 2, 2, 0.", "*DLOAD"]
        out += [f"{e}, P2, {p:.10g}" for e in top]
        out += ["*NODE PRINT, NSET=NTOP", "RF", "*CONTACT PRINT", "CSTR, CSDV", "*END STEP"]
    return "\n".join(out) + "\n"


def slave_areas(n=3, side=10.0):
    """Contact area of each slave node (mm^2): a quarter of each adjacent face."""
    a = (side / n) ** 2
    w = np.zeros((n + 1, n + 1))
    for j in range(n):
        for i in range(n):
            w[j : j + 2, i : i + 2] += a / 4
    return {SLAVE0 + k: float(v) for k, v in enumerate(w.ravel())}


_KINDS = {
    "forces": "forces",
    "contact stress": "stress",
    "relative contact displacement": "disp",
    "contact state variables": "sdv",
    "equivalent plastic strain": "peeq",
    "total force": "total",
}
_HEAD = re.compile(
    r"\s*(forces|contact stress|relative contact displacement|contact state variables"
    r"|equivalent plastic strain|total force)"
    r" .*time\s*(\S+)"
)


def read_blocks(path):
    """Output times of a ``.dat`` file: ``[(time, {kind: rows})]``, rows in the file's order.

    Kinds: ``forces`` (``*NODE PRINT, RF``), ``total`` (the same with ``TOTALS=ONLY``),
    ``stress`` (``*CONTACT PRINT, CSTR``), ``disp`` (``CDIS``), ``sdv`` (``CSDV``), ``peeq``
    (``*EL PRINT, PEEQ``: element, integration point, value). A row is the tuple of the line's numbers: node-to-surface
    contact ``(node, ...)``, face-to-face ``(element, face, ...)`` (``sdv``: ``(element, face,
    integration point, ...)``). Other blocks of the file are skipped.
    """
    blocks = {}
    cur = None
    for line in Path(path).read_text().splitlines():
        m = _HEAD.match(line)
        if m:
            kind = _KINDS[m.group(1)]
            cur = blocks.setdefault(float(m.group(2)), {}).setdefault(kind, [])
            continue
        parts = line.split()
        if not parts:
            continue
        try:
            row = tuple(float(v) for v in parts)
        except ValueError:
            cur = None
            continue
        if cur is not None:
            cur.append(row)
    return sorted(blocks.items())


def read_dat(path):
    """Output times of a node-to-surface ``.dat`` file: ``[(time, forces, contact)]``.

    ``forces[node] = (fx, fy, fz)`` of ``*NODE PRINT, RF``; ``contact[node] = (p, tau1, tau2)``
    of ``*CONTACT PRINT, CSTR``.
    """
    out = []
    for t, b in read_blocks(path):
        forces = {int(r[0]): r[1:] for r in b.get("forces", [])}
        contact = {int(r[0]): r[1:] for r in b.get("stress", [])}
        out.append((t, forces, contact))
    return out


def _swift_table(K=530.0, eps0=0.006, n=0.24, eps_max=3.0, points=60):
    """``*PLASTIC`` rows (MPa, plastic strain) of the Swift curve, denser at small strain."""
    ep = np.concatenate([[0.0], np.geomspace(1e-4, eps_max, points - 1)])
    return [f"{K * (eps0 + e) ** n:.8g}, {e:.8g}" for e in ep]


def _flat_die(nd, r_max, z0, thickness):
    """An axisymmetric flat die of two CAX4 layers (nodes and elements from 100001), ``nd``
    elements from r = 0 to ``r_max`` at ``z0 <= z <= z0 + thickness``: ``(node lines, element
    lines, its underside's elements, its top nodes)``."""
    rd, zd = np.linspace(0.0, r_max, nd + 1), np.linspace(z0, z0 + thickness, 3)
    ids = np.arange((nd + 1) * 3).reshape(3, nd + 1) + 100001
    nodes = [f"{ids[k, i]}, {rd[i]:.10g}, {zd[k]:.10g}" for k in range(3) for i in range(nd + 1)]
    elements = [
        f"{100001 + i + nd * k}, {ids[k, i]}, {ids[k, i + 1]}, {ids[k + 1, i + 1]}, {ids[k + 1, i]}"
        for k in range(2)
        for i in range(nd)
    ]
    return nodes, elements, list(range(100001, 100001 + nd)), list(ids[-1])


def ring(interaction, *, nr=12, nz=None, od=18.0, idia=9.0, h=6.0, reduction=0.3, n_inc=30):
    """Axisymmetric ring compression (CAX4, half height, mm): the deck of ``fe-demo ring``.

    The ring's upper half (symmetry at z = 0) under a flat die of 1000x steel's stiffness whose
    top is moved down by ``reduction * h / 2`` in ``n_inc`` fixed increments; DC04's Swift curve
    (fe_demo.solver.material.DC04) as isotropic hardening, NLGEOM. Node 1 is the inner mid-plane node;
    the die's top nodes form NDIE.
    """
    ri, ro, hh = idia / 2, od / 2, h / 2
    if nz is None:
        nz = max(1, round(nr * hh / (ro - ri)))
    rs, zs = np.linspace(ri, ro, nr + 1), np.linspace(0.0, hh, nz + 1)
    ids = np.arange((nr + 1) * (nz + 1)).reshape(nz + 1, nr + 1) + 1
    out = ["*HEADING", "ring compression, user friction", "*NODE"]
    out += [
        f"{ids[k, i]}, {rs[i]:.10g}, {zs[k]:.10g}" for k in range(nz + 1) for i in range(nr + 1)
    ]
    # die: r from 0 to 1.5 od, 2 layers, elements about the ring's size
    nd = int(np.ceil(1.5 * ro / ((ro - ri) / nr)))
    die_nodes, die_elements, bottom, die_top = _flat_die(nd, 1.5 * ro, hh, 1.0)
    out += die_nodes
    out.append("*ELEMENT, TYPE=CAX4R, ELSET=ERING")
    e = 1
    faces = []  # the top face and the free sides, which fold onto the die as the ring barrels
    for k in range(nz):
        for i in range(nr):
            out.append(f"{e}, {ids[k, i]}, {ids[k, i + 1]}, {ids[k + 1, i + 1]}, {ids[k + 1, i]}")
            if k == nz - 1:
                faces.append(f"{e}, S3")
            if i == 0:
                faces.append(f"{e}, S4")
            if i == nr - 1:
                faces.append(f"{e}, S2")
            e += 1
    out += ["*ELEMENT, TYPE=CAX4, ELSET=EDIE", *die_elements]
    # CAX4 faces: S1 = nodes 1-2 (bottom), S2 = 2-3 (outer), S3 = 3-4 (top), S4 = 4-1 (inner)
    out += ["*SURFACE, NAME=SRING", *faces]
    out += ["*SURFACE, NAME=SDIE", *[f"{el}, S1" for el in bottom]]
    out += ["*NSET, NSET=NSYM", *[f"{v}," for v in ids[0]]]
    out += ["*NSET, NSET=NDIE", *[f"{v}," for v in die_top]]
    out += ["*NSET, NSET=NINNER", "1,"]
    out += [
        "*MATERIAL, NAME=DC04",
        "*ELASTIC",
        "210000., 0.3",
        "*PLASTIC",
        *_swift_table(),
        "*MATERIAL, NAME=DIE",
        "*ELASTIC",
        "2.1e8, 0.3",
        "*SOLID SECTION, ELSET=ERING, MATERIAL=DC04",
        "*SOLID SECTION, ELSET=EDIE, MATERIAL=DIE",
        *interaction,
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
        "1e6, 0.01",
        f"*CONTACT PAIR, INTERACTION={interaction[0].split('NAME=')[1].strip()}, "
        "TYPE=NODE TO SURFACE",
        "SRING, SDIE",
        "*BOUNDARY",
        "NSYM, 2, 2, 0.",
        "NDIE, 1, 1, 0.",
        f"*STEP, NLGEOM, INC={10 * n_inc}",
        "*STATIC",
        f"{1.0 / n_inc:.10g}, 1.0, 1e-5, {1.0 / n_inc:.10g}",
        "*BOUNDARY",
        f"NDIE, 2, 2, {-reduction * hh:.10g}",
        "*NODE PRINT, NSET=NDIE, TOTALS=ONLY",
        "RF",
        "*NODE PRINT, NSET=NINNER",
        "U",
        "*END STEP",
    ]
    return "\n".join(out) + "\n"


def plastic_block(
    steps,
    interaction,
    *,
    contact="SURFACE TO SURFACE",
    static="1., 1., 1e-6, 1.",
    contact_print=("CSTR", "CSDV"),
    slope=1e6,
    si=False,
    element="C3D8I",
    plastic=True,
    plate=(6, 4),
):
    """A 12 x 8 x 4 mm elastic-plastic block (``element``, 6 x 4 x 2) on a 24 x 16 x 4 mm
    elastic plate (C3D8, 6 x 4 x 1), mm-t-s (``si``: the same deck in m and Pa).

    The block yields at 250 MPa and hardens linearly to 700 MPa at a plastic strain of 0.5
    (``plastic=False``: elastic); its bottom is the slave surface. ``plate``: the plate's
    elements along x and y. Each step of ``steps``, ``(pressure_MPa, ux_mm)``, ramps
    the pressure on the block's top and the top's sideways displacement from the previous
    step's values, with automatic incrementation ``static`` (the ``*STATIC`` data line:
    initial increment, period, minimum, maximum).
    """
    ln, st = (1e-3, 1e6) if si else (1.0, 1.0)
    npl, epl, ipl = _block(
        (-6 * ln, -4 * ln, -4 * ln), (24 * ln, 16 * ln, 4 * ln), (*plate, 1), 1, 1
    )
    nbl, ebl, ibl = _block((0, 0, 0), (12 * ln, 8 * ln, 4 * ln), (6, 4, 2), SLAVE0, 1001)
    out = ["*HEADING", "elastic-plastic block on a plate", "*NODE"]
    for nodes in (npl, nbl):
        out += [f"{k}, {x:.10g}, {y:.10g}, {z:.10g}" for k, (x, y, z) in nodes.items()]
    out.append("*ELEMENT, TYPE=C3D8, ELSET=EPLATE")
    out += [f"{e}, " + ", ".join(map(str, c)) for e, (_, c) in epl.items()]
    out.append(f"*ELEMENT, TYPE={element}, ELSET=EBLOCK")
    out += [f"{e}, " + ", ".join(map(str, c)) for e, (_, c) in ebl.items()]
    out += ["*SURFACE, NAME=SMASTER", *[f"{e}, S2" for e in epl]]
    out += ["*SURFACE, NAME=SSLAVE", *[f"{e}, S1" for e, (k, _) in ebl.items() if k == 0]]
    out += ["*NSET, NSET=NBASE", *[f"{v}," for v in ipl[0].ravel()]]
    out += ["*NSET, NSET=NTOP", *[f"{v}," for v in ibl[-1].ravel()]]
    out += [
        "*MATERIAL, NAME=PLATE",
        "*ELASTIC",
        f"{210000.0 * st:.10g}, 0.3",
        "*MATERIAL, NAME=BLOCK",
        "*ELASTIC",
        f"{210000.0 * st:.10g}, 0.3",
        *(["*PLASTIC", f"{250.0 * st:.10g}, 0.", f"{700.0 * st:.10g}, 0.5"] if plastic else []),
        "*SOLID SECTION, ELSET=EPLATE, MATERIAL=PLATE",
        "*SOLID SECTION, ELSET=EBLOCK, MATERIAL=BLOCK",
        *_contact(interaction, contact, slope * st / ln, 0.01 * st),
    ]
    top = [e for e, (k, _) in ebl.items() if k == 1]
    for p, ux in steps:
        out += ["*STEP, INC=1000", "*STATIC", static, "*BOUNDARY"]
        out += [f"NTOP, 1, 1, {ux * ln:.10g}", "NTOP, 2, 2, 0."]
        out += ["*DLOAD", *[f"{e}, P2, {p * st:.10g}" for e in top]]
        out += ["*NODE PRINT, NSET=NTOP, TOTALS=ONLY", "RF", "*CONTACT PRINT"]
        out += [", ".join(contact_print), "*END STEP"]
    return "\n".join(out) + "\n"


def billet(interaction, *, element="CAX4", contact="SURFACE TO SURFACE", nr=8, nz=4, n_inc=30):
    """Axisymmetric upsetting of a solid billet (radius 10 mm, half height 5 mm with symmetry at
    z = 0, ``nr`` x ``nz`` elements ``element``) under a stiff flat die (CAX4, 16 x 2 elements
    out to r = 15 mm), NLGEOM, upset by 30 % (the die moves 1.5 mm) in ``n_inc`` increments of
    ccx's automatic incrementation. The billet yields at 250 MPa and hardens linearly to 700 MPa
    at a plastic strain of 0.5. Slave surface: the billet's top (S3) and its free side (S2),
    which folds onto the die as the billet barrels; master: the die's underside.

    The deck of a user's report: face-to-face with CAX4 and the routine it stopped at 29 % with
    "too many cutbacks" (ccx's cut-back softens face-to-face contact 100-fold, which the
    routine's stick stiffness did not follow; then a NaN from ccx's own re-layout).
    """
    r, hh = 10.0, 5.0
    step = 2 if element.startswith("CAX8") else 1
    nx, nzz = step * nr + 1, step * nz + 1
    rs, zs = np.linspace(0.0, r, nx), np.linspace(0.0, hh, nzz)

    def nid(i, k):
        return 1 + i + nx * k

    out = ["*HEADING", f"axisymmetric billet ({element}) upset by a flat die", "*NODE"]
    out += [
        f"{nid(i, k)}, {rs[i]:.10g}, {zs[k]:.10g}"
        for k in range(nzz)
        for i in range(nx)
        if not (step == 2 and i % 2 and k % 2)
    ]
    die_nodes, die_elements, underside, die_top = _flat_die(2 * nr, 1.5 * r, hh, 2.0)
    out += die_nodes
    out.append(f"*ELEMENT, TYPE={element}, ELSET=EBILLET")
    slave = []
    e = 1
    for k in range(nz):
        for i in range(nr):
            a, b = step * i, step * k
            c = [nid(a, b), nid(a + step, b), nid(a + step, b + step), nid(a, b + step)]
            if step == 2:
                c += [nid(a + 1, b), nid(a + 2, b + 1), nid(a + 1, b + 2), nid(a, b + 1)]
            out.append(f"{e}, " + ", ".join(map(str, c)))
            slave += [f"{e}, S3"] * (k == nz - 1) + [f"{e}, S2"] * (i == nr - 1)
            e += 1
    out += ["*ELEMENT, TYPE=CAX4, ELSET=EDIE", *die_elements]
    out += ["*SURFACE, NAME=SSLAVE", *slave]
    out += ["*SURFACE, NAME=SMASTER", *[f"{el}, S1" for el in underside]]
    out += ["*NSET, NSET=NSYM", *[f"{nid(i, 0)}," for i in range(nx)]]
    out += ["*NSET, NSET=NDIE", *[f"{v}," for v in die_top]]
    out += [
        "*MATERIAL, NAME=BILLET",
        "*ELASTIC",
        "210000., 0.3",
        "*PLASTIC",
        "250., 0.",
        "700., 0.5",
        "*MATERIAL, NAME=DIE",
        "*ELASTIC",
        "2.1e8, 0.3",
        "*SOLID SECTION, ELSET=EBILLET, MATERIAL=BILLET",
        "*SOLID SECTION, ELSET=EDIE, MATERIAL=DIE",
        *_contact(interaction, contact, 1e6, 0.01)[:-2],
        "*BOUNDARY",
        "NSYM, 2, 2, 0.",
        "NDIE, 1, 1, 0.",
        "*STEP, NLGEOM, INC=1000",
        "*STATIC",
        f"{1.0 / n_inc:.6g}, 1.0, 1e-5, {1.0 / n_inc:.6g}",
        "*BOUNDARY",
        f"NDIE, 2, 2, {-0.3 * hh:.10g}",
        "*NODE PRINT, NSET=NDIE, TOTALS=ONLY",
        "RF",
        "*CONTACT PRINT",
        "CSTR, CSDV",
        "*END STEP",
    ]
    return "\n".join(out) + "\n"
