"""Texts of the exported folders: READMEs and the table decks (private)."""

__all__ = ["fortran_readme", "table_readme", "abaqus_table", "lsdyna_table"]

_STATE = """\
State per contact point (the host keeps it only for converged increments):

| index | meaning | required |
|---|---|---|
| 1 | `p_hist`: the largest contact pressure the point has carried ({s}) | yes |
| 2 | cache of `-ln alpha1(p_hist)`, written with `p_hist` (saves the Eq. 25 branch a `g` evaluation; `<= 0` means "recompute") | no |
| 3 | status of the last call: 0 open, 1 stick, 2 slip (output only) | no |

Start the analysis with all state variables zero (the host's default): `p_hist = 0` is a virgin
surface. To start from a pre-loaded surface set `{arr}1{end}` and leave `{arr}2{end} = 0`.
"""

_LAW = """\
The law: `tau = m k (1 + geo_ratio) alpha`, `alpha = alpha1(p)` (Eq. 24) while `p >= p_hist`,
`alpha = alpha2(p, p_hist)` (Eq. 25) below it{cont}; `p <= 0` gives zero traction. It is evaluated
exactly as `frictionlaw`'s kernels do (no NaN or overflow for any finite input).
"""


def _law(params):
    cont = (
        ", normalised to meet Eq. 24 at `p_hist` (continuous_reload)"
        if params.continuous_reload
        else ""
    )
    return _LAW.format(cont=cont)


def _units(units):
    if units.name == "SI":
        return "Units: SI (Pa, m, N). The model must use SI units."
    return (
        "Units: mm-tonne-s (MPa = N/mm^2, mm, N). Pressures, `p_hist`, `tau_max` and `H` are in MPa; "
        "a tangential stiffness is in MPa/mm = N/mm^3."
    )


def _kt_text(target, kt, units):
    if target == "lsdyna-usrfrc-mpp":
        return (
            "Stick: LS-DYNA's own Coulomb return map with its contact penalty applies the "
            "coefficient this routine returns; no stiffness is compiled in."
        )
    if target == "lsdyna-usrfrc" and kt.kind == "host":
        return (
            "Stick stiffness: LS-DYNA's contact penalty `STFK` (per slave node, as in LSTC's "
            "sample `usrfrc`), as a traction stiffness `STFK SFACN3 / AREAS`."
        )
    if target in ("abaqus-vfric", "abaqus-vfriction"):
        return (
            "Stick: Abaqus/Explicit passes the stick force (the force that stops the relative "
            "motion in this increment); the routine returns it when it is within "
            "`tau(p, p_hist) x area`, so no stiffness is needed."
        )
    text = "Stick stiffness: " + kt.describe(units) + "."
    if kt.kind == "host" and target in ("abaqus-fric", "calculix"):
        text += (
            " Abaqus' own convention is used: elastic slip 0.005 x CHRLNGTH, i.e. "
            "`k_t = tau(p, p_hist) / (0.005 CHRLNGTH)` (at least the smallest normal double "
            "over it)."
        )
    elif kt.kind == "host":
        text += " The calling glue passes the host's tangential penalty as `KHOST`."
    return text


_STATE_ARRAY = {
    "abaqus-vfriction": ("state(", ", j, k)"),
    "lsdyna-usrfrc": ("UFHIST(", ", ILBSV(II))"),
    "lsdyna-usrfrc-mpp": ("UH(", ")"),
    "lsdyna": ("history variable ", ""),
    "ansys-userfric": ("state variable ", ""),
}


def fortran_readme(target, name, params, units, kt, sha):
    """README of a Fortran target."""
    arr = _STATE_ARRAY.get(target, ("STATEV(", ")"))
    body = {
        "abaqus-fric": _ABAQUS_FRIC,
        "abaqus-vfric": _ABAQUS_VFRIC,
        "abaqus-vfriction": _ABAQUS_VFRICTION,
        "lsdyna-usrfrc": _LSDYNA_USRFRC,
        "lsdyna-usrfrc-mpp": _LSDYNA_USRFRC_MPP,
        "lsdyna": _LSDYNA,
        "ansys-userfric": _ANSYS,
        "calculix": _CALCULIX,
    }[target]
    return (
        f"# `{target}`: SBMF friction law as a user subroutine\n\n"
        f"File: `{name}` (fixed-form Fortran, double precision; parameter file sha256 `{sha}`).\n\n"
        + _law(params)
        + "\n"
        + _units(units)
        + "\n\n"
        + _kt_text(target, kt, units)
        + "\n\n"
        + body.format(name=name)
        + "\n"
        + _STATE.format(s=units.stress_unit, arr=arr[0], end=arr[1])
        + (_TESTED_CALCULIX if target == "calculix" else _TESTED_EMULATED)
    )


_TESTED_EMULATED = (
    "\nTested here: compiled with gfortran -Wall and driven by a harness that emulates the "
    "host's documented calling sequence (iterations, converged increments, cut-backs) against "
    "`frictionlaw.traction_update`; no commercial solver runs in this project. See "
    "docs/fe_codes.md of the sbmf-friction project.\n"
)
_TESTED_CALCULIX = (
    "\nTested here: ccx built by `build.sh` runs blocks pressed, slid, unloaded and reloaded, and "
    "a ring compression; the friction force is checked against `frictionlaw.shear_limit` node by "
    "node (tests/test_calculix.py of the sbmf-friction project).\n"
)


_ABAQUS_FRIC = """\
## Compile and activate (Abaqus/Standard)

    abaqus job=<job> input=<model>.inp user={name}

Input deck (no PROPERTIES: the constants are compiled in; NPROPS = 0):

    *SURFACE INTERACTION, NAME=SBMF
    *FRICTION, USER, DEPVAR=3

`DEPVAR=1` is enough (`p_hist` only); 2 adds the `-ln alpha1(p_hist)` cache; 3 the status output
(request `SDV` contact output to see them).

Interface relied upon (Abaqus User Subroutines Reference, FRIC): `TAU` and `STATEV` are passed in
as the values at the start of the increment, `DGAM` is the slip increment since then, `PRESS` the
current contact pressure; Abaqus keeps `STATEV` only when the increment converges and restores it
on a cut-back. The routine returns `LM = 0` (relative motion: elastic stick or slip) with `TAU`,
`DDTDDG`, `DDTDDP`, `DSLIP`, `SED`, `SFD`, or `LM = 2` (no friction) when `PRESS <= 0`.
`DDTDDP` is unsymmetric: use `*CONTACT PAIR ... UNSYMM=YES`/the unsymmetric solver to use it.
"""

_CALCULIX = """\
## Build ccx with the routine (CalculiX 2.20, Debian 12)

CalculiX has no user friction routine; `calculix-2.20-user-friction.patch` adds Abaqus' form
`*FRICTION, USER, DEPVAR=n[, PROPERTIES=m]` to its node-to-surface penalty contact and calls the
routine `{name}` (the `abaqus-fric` routine, unchanged) per slave node. `build.sh` fetches Debian's
`calculix-ccx` 2.20 source (`apt-get source`: it needs a `deb-src` entry), applies the patch, builds
it and links the routine in:

    apt-get install -y dpkg-dev gfortran gcc make patch libspooles-dev libarpack2-dev liblapack-dev
    bash build.sh            # prints the path of ./ccx; --help lists the options

About 2 minutes on 2 cores; `ccx-build/` keeps the objects, so relinking another export's routine
(`bash build.sh --routine other/sbmf_fric.f --out other/ccx`) takes seconds. `ccx-build/ccx_reference`
is the same source without the patch.

Input deck (node-to-surface contact, `*CONTACT PAIR, ..., TYPE=NODE TO SURFACE`):

    *SURFACE INTERACTION, NAME=SBMF
    *SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR
    <slope>, <tension at large clearance>
    *FRICTION, USER, DEPVAR=3

Limits of the patch: face-to-face and mortar contact stop with an error; KSTEP, KINC, TIME, DTIME,
DPRESS, DDPDDH, PREDEF, the surface names and DROT are not passed (0, blanks, identity: CalculiX
does not hand them to its contact springs); PNEWDT is ignored; LM = 1 (sticking) is taken as LM = 0.
The state (the routine's STATEV and the frictional stress) is committed with each converged
increment and restored on a cut-back, as CalculiX does for its own slip state. See docs/fe_codes.md
of the sbmf-friction project. The patch is GPL v2, as CalculiX.
"""

_ABAQUS_VFRIC = """\
## Compile and activate (Abaqus/Explicit)

    abaqus job=<job> input=<model>.inp user={name}

Input deck (contact pair algorithm; VFRIC cannot be used with general contact):

    *SURFACE INTERACTION, NAME=SBMF
    *FRICTION, USER=VFRIC, DEPVAR=3

Interface relied upon (Abaqus User Subroutines Reference, VFRIC): per contact point `fNormal`
(normal force), `fStickForce` (the force that would stop the relative motion), `areaSec` (area of
the secondary node), `statev(nStateVar, nSecNod)` per secondary node; `fTangential(1)` must lie in
`[-fStickForce, 0]`. Explicit has no iterations and no cut-backs: the history is updated in every
increment.
"""

_LSDYNA = """\
## Use in LS-DYNA

The file holds the law core and the host-neutral entry point `SBMF_FRICTION` (one contact point
per call; arguments documented in the file). LS-DYNA's user friction is compiled into a user
executable from the object files LS-DYNA ships (routine `usrfrc` in `dyn21.f`, activated with
`*USER_INTERFACE_FRICTION` and the contact's user-friction flag; LS-DYNA Keyword User's Manual,
Vol. I, `*USER_INTERFACE_FRICTION`, and the manual's appendix on user-defined friction).
For the `usrfrc` argument list of LSTC's `dyn21.f` use the drop-in targets `lsdyna-usrfrc` (SMP)
and `lsdyna-usrfrc-mpp` (MPP) instead. This file is for a release whose template differs: call
`SBMF_FRICTION` from it with

- `P` = normal force / contact area of the segment, `ND` = 2,
- `PH`, `G1H` = history variables 1 and 2 of the contact point (`NHSV >= 2`),
- `DU`, `TOLD` = the tangential slip increment and traction of the last converged cycle,

and store `PHNEW`, `G1NEW` back into the history variables (explicit: every cycle commits).
Add `{name}` to the user-executable build (e.g. append it to `dyn21.f`).
"""

_ABAQUS_VFRICTION = """\
## Compile and activate (Abaqus/Explicit, general contact)

    abaqus job=<job> input=<model>.inp user={name}

Input deck (general contact; `VFRICTION` is the friction routine of `*CONTACT`):

    *SURFACE INTERACTION, NAME=SBMF
    *FRICTION, USER=VFRICTION, DEPVAR=3
    *CONTACT
    *CONTACT INCLUSIONS, ALL EXTERIOR
    *CONTACT PROPERTY ASSIGNMENT
     , , SBMF

(or name the two surfaces on the `*CONTACT PROPERTY ASSIGNMENT` data line to use the law only
between the sheet and a tool). `DEPVAR=1` is enough (`p_hist` only); 2 adds the cache; 3 the
status. Check the `*FRICTION, USER=VFRICTION` spelling against your release's Keywords
Reference (`*FRICTION`: `USER=VFRIC` for contact pairs, `USER=VFRICTION` for general contact).

Interface relied upon (Abaqus User Subroutines Reference, "VFRICTION", e.g. the public 2017
edition): blocks of `nBlock` contact points with `fNormal`, `areaCont`, `fStickForce` (the force
that would stop the relative motion), `state(nStates, nNodState, nBlock)` with
`nNodState = 1` for node-type secondary surfaces and more for edge-type ones; `fTangential(1)`
must lie in `[-fStickForce, 0]`. For an edge-type point the routine takes the largest `p_hist` of
its state nodes and raises every one of them to at least the current pressure. Explicit has no
iterations and no cut-backs: the history is updated in every increment.
"""

_LSDYNA_USRFRC = """\
## Compile and activate (LS-DYNA SMP, user executable)

Add `{name}` to the user-object build in place of the sample `usrfrc` of `dyn21.f` (delete or
rename the sample: only one `usrfrc` may be linked) and build with the makefile LS-DYNA ships, so
that this file gets the same flags as `dyn21.f` (double precision: ifort `-r8 -i8`, or with
gfortran `-fdefault-real-8 -fdefault-double-8 -fdefault-integer-8`; single precision: none).
With OpenMP (`-qopenmp`/`-fopenmp`) the routine is safe to call from several threads (no SAVE,
COMMON or DATA).

Keyword input (LS-DYNA Keyword User's Manual Vol. I; field names to check against your
release, they were taken from the manual's description, not from a run):

- `*USER_INTERFACE_FRICTION` for the contact interface (the interface number, and the user
  parameters: none are needed, the constants are compiled in),
- `*CONTROL_CONTACT`, card 2, `USRFRC` = storage per contact interface for the user friction
  routine, and the number of user friction history variables per slave node (`NHV` in the
  routine) at least 1 (3 to also get the cache and the status),
- a forming contact (`*CONTACT_FORMING_...`) or another type whose `areas` argument is the slave
  node area: LSTC's sample comments say `areas` is defined for interface types 5 and 10 and for
  forming contacts; the pressure `p = -FNI/AREAS` needs it.

What the routine does per active slave node (LSTC's sample conventions): `p = -FNI/AREAS`; trial
friction force = tangential part of `FDAT(3:5)` (the old friction force) + `STFK SFACN3 (DX, DY,
DZ)`; the law's return map (stick within `tau(p, p_hist) AREAS`, else radial return); the new
force is stored in `FDAT(3:5)` and added to `FXIS, FYIS, FZIS`; `ISEG` and `FDAT(1:2)` are set
as in the sample. `UFHIST(1, ILBSV(II))` = `p_hist`, committed every cycle (explicit). `FNI >= 0`
or `AREAS <= 0` is open: no friction, `FDAT(3:5) = 0`, history unchanged. The keyword's `FS, FD,
DC, VC` and `FSF/VSF` are not used. In a single-precision executable `p_hist` is stored rounded
down to single precision (so that a constant pressure stays on Eq. 24) and state 2 (the cache)
is not used (a rounded cache would change Eq. 25 by 1e-7).
"""

_LSDYNA_USRFRC_MPP = """\
## Compile and activate (LS-DYNA MPP, user executable)

Add `{name}` to the MPP user-object build in place of the sample MPP `usrfrc` of `dyn21.F`, with
the same flags as `dyn21.F` (see the SMP target). Keyword input as for the SMP target
(`*USER_INTERFACE_FRICTION`, user friction history variables `NH >= 1`); to be checked against
your release.

The MPP interface is a coefficient interface: per slave node LS-DYNA passes the interface
pressure `PRS` and the history `UH(NH)` and takes back the static and dynamic coefficients
`FSTT, FDYN`, which it then applies in its own Coulomb return map. The routine returns
`FSTT = FDYN = tau(p, p_hist)/p` (so the decay `DC` has no effect) and keeps `UH(1) = p_hist`.

What is lost against the SMP routine: the stick stiffness is LS-DYNA's contact penalty (a
calibrated `k_t` table cannot be used); the coefficient is formed from LS-DYNA's `PRS`, whose
definition (segment- or node-based) the public sample does not state; the MPP sample does not
say whether `UH` is committed once per cycle, which the routine assumes (as for explicit
analysis); the viscous cap `VC` and `FSF` must be left at their defaults (0 and 1). The law
itself (Eqs. 24-26 with `p_hist`) is carried exactly: `mu p = tau(p, p_hist)` at slip.
"""

_ANSYS = """\
## Use in ANSYS Mechanical APDL (CONTA17x)

The file holds the law core and the host-neutral entry point `SBMF_FRICTION` (one contact point
per call; arguments documented in the file). ANSYS calls `USERFRIC` for contact elements
CONTA172/174/175/177 whose material is defined with `TB,FRIC,,,,USER` (Programmer's Reference,
"Subroutines for Customizing Contact Interfacial Behavior", `userfric`); the state variables are
declared with `NSVR` and the routine is linked into a custom executable (`ANSCUSTOM`) or a user
library (`ANS_USER_PATH`). The exact argument list of `userfric` differs between releases and
could not be checked from public documentation for this export, so no `USERFRIC` wrapper is
generated: call `SBMF_FRICTION` from the `userfric.F` template of your release with

- `P` = the contact pressure, `ND` = 1 (2-D) or 2 (3-D),
- `PH`, `G1H` = state variables 1 and 2 as at the start of the substep,
- `DU` = the tangential slip increment of the substep, `TOLD` = the traction at its start,
- `KHOST` = the tangential penalty stiffness ANSYS passes (used only without a calibrated k_t),

return `TNEW` as the frictional stress, `DTDDU`/`DTDP` as its derivatives, and store `PHNEW`,
`G1NEW` as the new state (ANSYS keeps state only for converged substeps).
"""


def table_readme(target, name, params, units, table, sha):
    """README of a table target."""
    s = units.stress_unit
    host = {
        "abaqus-table": (
            "Abaqus: include the deck lines under the interaction (`*INCLUDE, INPUT=" + name + "`"
            " below `*SURFACE INTERACTION`, or paste them). Abaqus interpolates `mu` linearly in "
            "the contact pressure and holds it constant beyond the end points; `TAUMAX` caps the "
            "shear at `m k (1 + geo_ratio)`."
        ),
        "lsdyna-table": (
            "LS-DYNA: the deck defines the curve of `mu` against pressure and a table over relative "
            "velocity (the same curve at every velocity). Reference the table from the contact "
            "with `FS = -2`, `FD = <table id>` and set `VC` (the viscous-friction cap, a shear "
            "stress) to the value given in the deck (LS-DYNA Keyword User's Manual, `*CONTACT`, "
            "card 2: FS, FD, VC). The last two points carry the same `mu` so that LS-DYNA's "
            "linear extrapolation beyond the curve stays flat."
        ),
    }[target]
    return (
        f"# `{target}`: SBMF first-loading law (Eq. 24) as a friction table\n\n"
        f"File: `{name}` (parameter file sha256 `{sha}`). {_units(units)}\n\n"
        f"{host}\n\n"
        f"Table: {len(table.p)} pressures from 0 to {table.p[-1] * units.stress:.6g} {s}, "
        f"`mu = tau(p)/p` of Eq. 24 at each (`mu_eff = {params.mu_eff:.6g}` at p = 0), "
        f"cap `tau_max = {table.tau_max * units.stress:.6g} {s}`. "
        f"Interpolation error, requested: `|tau_table - tau| <= {table.tol:g} tau_max`; "
        f"measured on an independent grid: {table.max_error:.3g} tau_max "
        f"(at p = {table.max_error_p * units.stress:.4g} {s}).\n\n"
        "What a table cannot do: it is a function of the current pressure only, so it cannot "
        "carry the history `p_hist`. Eq. 25 (the lower shear when the pressure falls below the "
        "largest pressure carried, and the reload back to Eq. 24) is lost; unloading follows "
        "Eq. 24 back down. Use a user-subroutine target where un-/reloading matters.\n"
    )


def _fmt(v):
    return f"{v:.10e}"


def abaqus_table(table, units):
    """Abaqus deck lines: ``*FRICTION, TAUMAX=`` with ``mu, slip rate, pressure`` data lines."""
    lines = [
        "** first-loading SBMF law (Eq. 24) as mu(contact pressure); no p_hist history",
        "** data lines: friction coefficient, slip rate (blank), contact pressure",
        f"*FRICTION, TAUMAX={_fmt(table.tau_max * units.stress)}",
    ]
    for p, mu in zip(table.p, table.mu, strict=True):
        lines.append(f"{_fmt(mu)}, , {_fmt(p * units.stress)}")
    return "\n".join(lines) + "\n"


def lsdyna_table(table, units, table_id=9100):
    """LS-DYNA keyword deck: mu(p) curves, a velocity table, and the contact's VC."""
    lines = [
        "$ first-loading SBMF law (Eq. 24) as mu(pressure); no p_hist history",
        f"$ on the contact card: FS = -2, FD = {table_id}, "
        f"VC = {_fmt(table.tau_max * units.stress)}",
        "*KEYWORD",
    ]
    p_last = table.p[-1] * units.stress
    for cid in (table_id + 1, table_id + 2):
        lines += ["*DEFINE_CURVE", "$     lcid", f"{cid:10d}", "$ pressure, mu"]
        for p, mu in zip(table.p, table.mu, strict=True):
            lines.append(f"{_fmt(p * units.stress)},{_fmt(mu)}")
        lines.append(f"{_fmt(1e3 * p_last)},{_fmt(table.mu[-1])}")
    lines += [
        "*DEFINE_TABLE",
        "$     tbid",
        f"{table_id:10d}",
        "$ relative velocity, curve id",
        f"{_fmt(0.0)},{table_id + 1}",
        f"{_fmt(1e20)},{table_id + 2}",
        "*END",
    ]
    return "\n".join(lines) + "\n"
