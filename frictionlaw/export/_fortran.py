"""Fixed-form Fortran sources of the law (Eqs. 24-26) and the host wrappers (private).

Every generated file is self-contained: the law core (``SBMF_SMIN``, ``SBMF_FIRST``,
``SBMF_RELOAD``, ``SBMF_SHEAR``, ``SBMF_KT``, ``SBMF_RMAP``) with the calibrated constants as
double-precision ``PARAMETER`` literals, followed by the host's entry point. The core follows
:mod:`frictionlaw._kernels` statement by statement (``smooth_min_log``, ``log_product``,
``sbmf_first_scalar``, ``sbmf_reload_scalar``, ``traction_row``: same branches, same operation
order, the law formed from logarithms, ``expm1`` and ``log1p`` from the C library through
``ISO_C_BINDING``), so that the compiled routine and the runtime agree to rounding.

State per contact point (the host keeps it only for converged increments):

1. ``p_hist``: the largest pressure carried so far (required).
2. ``G1H``: a cache of ``-ln alpha1(p_hist)`` (the logarithm the kernels' Eq. 25 works from,
   kept exactly so that the cached and the recomputed branch agree bitwise), written whenever
   ``p_hist`` is; ``<= 0`` means "not known" and it is recomputed (optional). It is ``>= 0``
   by construction and exactly 0 only where ``alpha1(p_hist) = 1`` to the last bit, which is
   then simply recomputed.
3. the status of the last call, 0 open, 1 stick, 2 slip (optional, output only).
"""

import math

__all__ = [
    "ABA_PARAM_INC",
    "core_source",
    "fric_source",
    "vfric_source",
    "vfriction_source",
    "usrfrc_smp_source",
    "usrfrc_mpp_source",
    "generic_source",
    "fortran_double",
]

_MAX_COLS = 72
#: Abaqus' ABA_PARAM.INC (implicit double precision, as the User Subroutines Reference gives it),
#: included by the FRIC routine: written beside it by the ``calculix`` target and by the harness
ABA_PARAM_INC = "      IMPLICIT REAL*8(A-H,O-Z)\n      PARAMETER (NPRECD=2)\n"


def fortran_double(v):
    """``v`` as a double-precision literal that reads back to the same float64."""
    s = f"{float(v):.17e}"
    mant, exp = s.split("e")
    return f"{mant}D{int(exp):+d}"


def _params_block(c, names, ratios=()):
    """``PARAMETER`` literals of ``c[names]``, then ``ratios`` ``(name, num, den)`` as ``num/den``.

    A ratio is folded by the compiler with one correctly rounded division, the value the
    kernels form at run time (``c1 = C1 / H``).
    """
    lines = ["      DOUBLE PRECISION " + ", ".join([*names, *(r[0] for r in ratios)])]
    for n in names:
        lines.append(f"      PARAMETER ({n} = {fortran_double(c[n])})")
    for name, num, den in ratios:
        lines.append(f"      PARAMETER ({name} = {num}/{den})")
    return lines


def _check_fixed_form(text):
    for i, line in enumerate(text.splitlines(), 1):
        if len(line) > _MAX_COLS:
            raise AssertionError(f"generated line {i} exceeds {_MAX_COLS} columns: {line!r}")
    return text


_SMIN_TEMPLATE = """\
C=======================================================================
C     Smooth minimum of Eqs. 24-25 from XL = ln X (frictionlaw's
C     smooth_min_log): G = tanh(Y)**(1/XN), Y = X**XN = exp(XN XL),
C     GOX = G/X, DG = dG/dX, GL = ln G. No X that under- or overflows
C     is formed. Y < 1D-4: series of ln(tanh(Y)/Y), so that G -> X
C     survives any XN; Y > 350: G = 1; else one expm1(-2Y). G itself
C     is formed only for XL >= 0 (X < 1 callers use GOX; G = 0 there).
C     X: exp(XL) when the caller formed it as a normal product (G/X is
C     then a division instead of an exp), else 0.
C=======================================================================
      SUBROUTINE SBMF_SMIN(XL, X, XN, G, GOX, DG, GL)
      IMPLICIT NONE
      DOUBLE PRECISION XL, X, XN, G, GOX, DG, GL
      DOUBLE PRECISION LNY, Y, Y2, LGOX, EM, TWOE, T, S
      DOUBLE PRECISION LNYSML, LNYSAT
      PARAMETER (LNYSML = {ln_small})
      PARAMETER (LNYSAT = {ln_sat})
      DOUBLE PRECISION SBMF_EXPM1, SBMF_LOG1P
      EXTERNAL SBMF_EXPM1, SBMF_LOG1P
      LNY = XN*XL
      IF (LNY .LT. LNYSML) THEN
        Y = EXP(LNY)
        Y2 = Y*Y
        LGOX = (-Y2/3.0D0 + 7.0D0*Y2*Y2/90.0D0)/XN
        GOX = EXP(LGOX)
C       XL < 0 here: callers take G/X (G is not formed, one exp less)
        G = 0.0D0
        DG = GOX*(1.0D0 - 2.0D0*Y2/3.0D0)
        GL = XL + LGOX
        RETURN
      END IF
      IF (LNY .GT. LNYSAT) THEN
        G = 1.0D0
        IF (X .GT. 0.0D0) THEN
          GOX = 1.0D0/X
        ELSE
          GOX = EXP(-XL)
        END IF
        DG = 0.0D0
        GL = 0.0D0
        RETURN
      END IF
      Y = EXP(LNY)
      EM = SBMF_EXPM1(-2.0D0*Y)
      TWOE = 2.0D0 + EM
      T = -EM/TWOE
      S = 4.0D0*Y*(1.0D0 + EM)/(-EM*TWOE)
      IF (Y .LT. 1.0D0) THEN
        LGOX = LOG(T/Y)/XN
        GOX = EXP(LGOX)
        G = 0.0D0
        DG = GOX*S
        GL = XL + LGOX
        RETURN
      END IF
      GL = SBMF_LOG1P(-2.0D0*(1.0D0 + EM)/TWOE)/XN
      G = EXP(GL)
      IF (X .GT. 0.0D0) THEN
        GOX = G/X
      ELSE
        GOX = EXP(GL - XL)
      END IF
      DG = GOX*S
      RETURN
      END
C
C     ln G alone (SBMF_SMIN's GL, the same statements): for
C     alpha1(p_hist) and the continuous variant's g(x2(PH)), where G,
C     G/X, dG/dX are not needed (one or two exps less).
      DOUBLE PRECISION FUNCTION SBMF_SMINL(XL, XN)
      IMPLICIT NONE
      DOUBLE PRECISION XL, XN
      DOUBLE PRECISION LNY, Y, Y2, EM, TWOE, T
      DOUBLE PRECISION LNYSML, LNYSAT
      PARAMETER (LNYSML = {ln_small})
      PARAMETER (LNYSAT = {ln_sat})
      DOUBLE PRECISION SBMF_EXPM1, SBMF_LOG1P
      EXTERNAL SBMF_EXPM1, SBMF_LOG1P
      LNY = XN*XL
      IF (LNY .LT. LNYSML) THEN
        Y = EXP(LNY)
        Y2 = Y*Y
        SBMF_SMINL = XL + (-Y2/3.0D0 + 7.0D0*Y2*Y2/90.0D0)/XN
        RETURN
      END IF
      IF (LNY .GT. LNYSAT) THEN
        SBMF_SMINL = 0.0D0
        RETURN
      END IF
      Y = EXP(LNY)
      EM = SBMF_EXPM1(-2.0D0*Y)
      TWOE = 2.0D0 + EM
      IF (Y .LT. 1.0D0) THEN
        T = -EM/TWOE
        SBMF_SMINL = XL + LOG(T/Y)/XN
        RETURN
      END IF
      SBMF_SMINL = SBMF_LOG1P(-2.0D0*(1.0D0 + EM)/TWOE)/XN
      RETURN
      END
C
C     ln(P C) for P, C > 0 without an under- or overflowing product.
      DOUBLE PRECISION FUNCTION SBMF_LPROD(P, C)
      IMPLICIT NONE
      DOUBLE PRECISION P, C, X
      X = P*C
      IF (1.0D-300 .LT. X .AND. X .LT. 1.0D+300) THEN
        SBMF_LPROD = LOG(X)
      ELSE
        SBMF_LPROD = LOG(P) + LOG(C)
      END IF
      RETURN
      END
C
"""


def _libm_wrapper(name):
    """``SBMF_<NAME>(Z)``: the C library's ``name`` through ``ISO_C_BINDING`` (fixed form)."""
    up = name.upper()
    return f"""\
      DOUBLE PRECISION FUNCTION SBMF_{up}(Z)
      USE, INTRINSIC :: ISO_C_BINDING
      IMPLICIT NONE
      DOUBLE PRECISION Z
      INTERFACE
        FUNCTION C_{up}(A) BIND(C, NAME='{name}')
          IMPORT :: C_DOUBLE
          REAL(C_DOUBLE), VALUE :: A
          REAL(C_DOUBLE) :: C_{up}
        END FUNCTION C_{up}
      END INTERFACE
      SBMF_{up} = C_{up}(Z)
      RETURN
      END
"""


def _smin():
    """The smooth minimum with the kernel's branch points as exact literals."""
    smin = _SMIN_TEMPLATE.format(
        ln_small=fortran_double(math.log(1e-4)), ln_sat=fortran_double(math.log(350.0))
    )
    return smin + _libm_wrapper("expm1") + "C\n" + _libm_wrapper("log1p")


_LAW_NAMES = ["TMAX", "H", "C1", "XN1", "C2", "XN2"]


def _law(c, continuous):
    """Eqs. 24, 25 and the branch selection, with the constants of ``c`` baked in."""
    first = [
        "C=======================================================================",
        "C     Eq. 24 (frictionlaw's sbmf_first_scalar): TAU = TMAX g(P C1/H;",
        "C     n1), DTAU = dTAU/dP; G1 = the cache value for p_hist = P,",
        "C     -ln alpha1(P).",
        "C=======================================================================",
        "      SUBROUTINE SBMF_FIRST(P, TAU, DTAU, G1)",
        "      IMPLICIT NONE",
        "      DOUBLE PRECISION P, TAU, DTAU, G1",
        "      DOUBLE PRECISION LNX1, X1, G, GOX, DG, GL",
        "      DOUBLE PRECISION SBMF_LPROD",
        "      EXTERNAL SBMF_LPROD",
        *_params_block(c, ["TMAX", "H", "C1", "XN1"], [("C1H", "C1", "H")]),
        "      LNX1 = SBMF_LPROD(P, C1H)",
        "      X1 = P*C1H",
        "      IF (.NOT. (1.0D-300 .LT. X1 .AND. X1 .LT. 1.0D+300)) X1 = 0.0D0",
        "      CALL SBMF_SMIN(LNX1, X1, XN1, G, GOX, DG, GL)",
        "      IF (LNX1 .LT. 0.0D0) THEN",
        "        TAU = P*(TMAX*C1H)*GOX",
        "      ELSE",
        "        TAU = TMAX*G",
        "      END IF",
        "      TAU = MIN(TAU, TMAX)",
        "      DTAU = TMAX*C1H*DG",
        "      G1 = -GL",
        "      RETURN",
        "      END",
        "C",
    ]
    if continuous:
        tau_lines = [
            "C     continuous_reload: divided by g(x2(PH); n2), formed in logs",
            "      LNX2H = SBMF_LPROD(PH, C2H) - LNA1H",
            "      LG2H = SBMF_SMINL(LNX2H, XN2)",
            "      SCL = EXP(-LG2H)",
            "      TAU = TMAX*EXP(LNA1H + LG2 - LG2H)",
            "      DTAU = TMAX*C2H*DG2*SCL",
        ]
        decl = [
            "      DOUBLE PRECISION LNX2H, LG2H, SCL",
        ]
    else:
        tau_lines = [
            "      IF (LNX2 .LT. 0.0D0) THEN",
            "C       alpha1(PH) cancels",
            "        TAU = P*(TMAX*C2H)*GOX2",
            "      ELSE",
            "        TAU = TMAX*A1H*G2",
            "      END IF",
            "      DTAU = TMAX*C2H*DG2",
        ]
        decl = []
    reload = [
        "C=======================================================================",
        "C     Eq. 25 below p_hist (frictionlaw's sbmf_reload_scalar):",
        "C     TAU = TMAX a1h g(x2; n2), a1h = alpha1(PH), x2 = P C2/(H a1h),",
        "C     all formed in logs (a1h -> 0 cannot overflow)."
        + (" Continuous" if continuous else ""),
        *(["C     variant: divided by g(x2(PH); n2) to meet Eq. 24 at PH."] if continuous else []),
        "C     Cap TMAX a1h for P <= PH, TMAX above. G1H: cached -ln a1h",
        "C     (<= 0: recompute it); G1OUT: the cache value for PH.",
        "C=======================================================================",
        "      SUBROUTINE SBMF_RELOAD(P, PH, G1H, TAU, DTAU, G1OUT)",
        "      IMPLICIT NONE",
        "      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT",
        "      DOUBLE PRECISION LNA1H, A1H, LNX2, X2, G2, GOX2, DG2, LG2, CAP",
        *decl,
        "      DOUBLE PRECISION SBMF_LPROD, SBMF_SMINL",
        "      EXTERNAL SBMF_LPROD, SBMF_SMINL",
        *_params_block(c, _LAW_NAMES, [("C1H", "C1", "H"), ("C2H", "C2", "H")]),
        "      G1OUT = G1H",
        "      IF (.NOT. (P .GT. 0.0D0 .AND. PH .GT. 0.0D0)) THEN",
        "        TAU = 0.0D0",
        "        DTAU = 0.0D0",
        "        RETURN",
        "      END IF",
        "      IF (G1H .GT. 0.0D0) THEN",
        "        LNA1H = -G1H",
        "      ELSE",
        "        LNA1H = SBMF_SMINL(SBMF_LPROD(PH, C1H), XN1)",
        "        G1OUT = -LNA1H",
        "      END IF",
        "      LNX2 = SBMF_LPROD(P, C2H) - LNA1H",
        "      A1H = EXP(LNA1H)",
        "C     x2 as a product where it is a normal double (saves an exp)",
        "      X2 = P*C2H",
        "      IF (1.0D-300 .LT. X2 .AND. X2 .LT. 1.0D+300 .AND.",
        "     &    A1H .GT. 1.0D-300) THEN",
        "        X2 = X2/A1H",
        "        IF (.NOT. (X2 .LT. 1.0D+300)) X2 = 0.0D0",
        "      ELSE",
        "        X2 = 0.0D0",
        "      END IF",
        "      CALL SBMF_SMIN(LNX2, X2, XN2, G2, GOX2, DG2, LG2)",
        *tau_lines,
        "      IF (P .LE. PH) THEN",
        "        CAP = TMAX*A1H",
        "      ELSE",
        "        CAP = TMAX",
        "      END IF",
        "      IF (TAU .GE. CAP) THEN",
        "        TAU = CAP",
        "        IF (P .GT. PH) DTAU = 0.0D0",
        "      END IF",
        "      RETURN",
        "      END",
        "C",
    ]
    shear = [
        "C=======================================================================",
        "C     Shear limit (Eqs. 24-26): Eq. 25 while P < PH, else Eq. 24;",
        "C     P <= 0 gives 0. G1OUT: the cache value for max(PH, P).",
        "C=======================================================================",
        "      SUBROUTINE SBMF_SHEAR(P, PH, G1H, TAU, DTAU, G1OUT)",
        "      IMPLICIT NONE",
        "      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT",
        "      G1OUT = G1H",
        "      IF (.NOT. (P .GT. 0.0D0)) THEN",
        "        TAU = 0.0D0",
        "        DTAU = 0.0D0",
        "        RETURN",
        "      END IF",
        "      IF (P .LT. PH) THEN",
        "        CALL SBMF_RELOAD(P, PH, G1H, TAU, DTAU, G1OUT)",
        "      ELSE",
        "        CALL SBMF_FIRST(P, TAU, DTAU, G1OUT)",
        "      END IF",
        "      RETURN",
        "      END",
        "C",
    ]
    return first + reload + shear


def _kt(kt):
    """``SBMF_KT(P, KFALL)``: the stick stiffness (table, constant, or the host's fallback)."""
    head = [
        "C=======================================================================",
        "C     Tangential stick stiffness k_t at pressure P (stress/length).",
    ]
    if kt.kind == "table":
        n = len(kt.log_p)
        body = [
            "C     Calibrated table k_t(p): log-log interpolation, constant beyond",
            "C     the end points (as frictionlaw.TangentialStiffness).",
            "C=======================================================================",
            "      DOUBLE PRECISION FUNCTION SBMF_KT(P, KFALL)",
            "      IMPLICIT NONE",
            "      DOUBLE PRECISION P, KFALL, LP, W",
            "      INTEGER NKT, J",
            f"      PARAMETER (NKT = {n})",
            "      DOUBLE PRECISION LPT(NKT), LKT(NKT), PLO, PHI, KLO, KHI",
            f"      PARAMETER (PLO = {fortran_double(kt.p[0])})",
            f"      PARAMETER (PHI = {fortran_double(kt.p[-1])})",
            f"      PARAMETER (KLO = {fortran_double(kt.k[0])})",
            f"      PARAMETER (KHI = {fortran_double(kt.k[-1])})",
        ]
        # named constants (PARAMETER arrays), not DATA: no static storage (thread safety)
        for name, vals in (("LPT", kt.log_p), ("LKT", kt.log_k)):
            body.append(f"      PARAMETER ({name} = (/")
            for j, v in enumerate(vals, 1):
                body.append(f"     &  {fortran_double(v)}" + (",", " /))")[j == len(vals)])
        body += [
            "      IF (KFALL .LT. 0.0D0) CONTINUE",
            "      IF (.NOT. (P .GT. PLO)) THEN",
            "        SBMF_KT = KLO",
            "        RETURN",
            "      END IF",
            "      IF (.NOT. (P .LT. PHI)) THEN",
            "        SBMF_KT = KHI",
            "        RETURN",
            "      END IF",
            "      LP = LOG(P)",
            "      J = 1",
            "   10 IF (J .LT. NKT - 1 .AND. LP .GE. LPT(J + 1)) THEN",
            "        J = J + 1",
            "        GOTO 10",
            "      END IF",
            "      W = (LKT(J + 1) - LKT(J))/(LPT(J + 1) - LPT(J))",
            "      SBMF_KT = EXP(W*(LP - LPT(J)) + LKT(J))",
            "      RETURN",
            "      END",
            "C",
        ]
        return head + body
    if kt.kind == "constant":
        return head + [
            "C     Constant value given at export time (--k-t).",
            "C=======================================================================",
            "      DOUBLE PRECISION FUNCTION SBMF_KT(P, KFALL)",
            "      IMPLICIT NONE",
            "      DOUBLE PRECISION P, KFALL",
            "      IF (P .LT. 0.0D0 .AND. KFALL .LT. 0.0D0) CONTINUE",
            f"      SBMF_KT = {fortran_double(kt.value)}",
            "      RETURN",
            "      END",
            "C",
        ]
    return head + [
        "C     No calibrated k_t in the parameter file: the host's KFALL.",
        "C=======================================================================",
        "      DOUBLE PRECISION FUNCTION SBMF_KT(P, KFALL)",
        "      IMPLICIT NONE",
        "      DOUBLE PRECISION P, KFALL",
        "      IF (P .LT. 0.0D0) CONTINUE",
        "      SBMF_KT = KFALL",
        "      RETURN",
        "      END",
        "C",
    ]


_RMAP = """\
C=======================================================================
C     Stick/slip return map (frictionlaw's traction_row): trial
C     TTR = TOLD + KT DU; stick if TAU > 0 and |TTR| <= TAU (tangent
C     KT I), else radial return TNEW = TAU n, tangent KT TAU/|TTR|
C     (I - n n), dTNEW/dP = DTAU n; TAU = 0 gives TNEW = 0 and a zero
C     tangent (slip). |TTR| = VMAX R, R = |TTR/VMAX|: nothing squared
C     under- or overflows. A trial that overflows is formed as TTR/S,
C     S = max(KT, |TOLD|) (it slips). ISTAT: 1 stick, 2 slip.
C=======================================================================
      SUBROUTINE SBMF_RMAP(ND, TAU, DTAU, DU, TOLD, KT, TNEW, DTDDU,
     &                     DTDP, ISTAT)
      IMPLICIT NONE
      INTEGER ND, ISTAT, A, B
      DOUBLE PRECISION TAU, DTAU, DU(ND), TOLD(ND), KT, TNEW(ND)
      DOUBLE PRECISION DTDDU(ND, ND), DTDP(ND), V, VMAX, S, KSC, R, Q
      DOUBLE PRECISION F
      LOGICAL STICK
      DO A = 1, ND
        DTDP(A) = 0.0D0
        DO B = 1, ND
          DTDDU(A, B) = 0.0D0
        END DO
      END DO
      VMAX = 0.0D0
      DO A = 1, ND
        V = TOLD(A) + KT*DU(A)
        TNEW(A) = V
        VMAX = MAX(VMAX, ABS(V))
      END DO
C     KSC = KT/S: the trial held in TNEW is TTR/S
      KSC = KT
      IF (.NOT. (VMAX .LE. HUGE(VMAX))) THEN
        S = KT
        DO A = 1, ND
          S = MAX(S, ABS(TOLD(A)))
        END DO
        KSC = KT/S
        VMAX = 0.0D0
        DO A = 1, ND
          V = TOLD(A)/S + KSC*DU(A)
          TNEW(A) = V
          VMAX = MAX(VMAX, ABS(V))
        END DO
      END IF
      R = 0.0D0
      IF (VMAX .GT. 0.0D0) THEN
        DO A = 1, ND
          Q = TNEW(A)/VMAX
          R = R + Q*Q
        END DO
        R = SQRT(R)
      END IF
      STICK = .FALSE.
      IF (KSC .EQ. KT .AND. TAU .GT. 0.0D0) THEN
C       VMAX = 0 (then R = 0) sticks: TAU/R would be +inf
        STICK = .NOT. (VMAX .GT. 0.0D0)
        IF (.NOT. STICK) STICK = VMAX .LE. TAU/R
      END IF
      IF (STICK) THEN
        DO A = 1, ND
          DTDDU(A, A) = KT
        END DO
        ISTAT = 1
        RETURN
      END IF
      ISTAT = 2
C     TAU = 0 and no trial traction: TNEW = 0, zero tangent
      IF (.NOT. (VMAX .GT. 0.0D0)) RETURN
      F = KSC*((TAU/VMAX)/R)
      DO A = 1, ND
        TNEW(A) = (TNEW(A)/VMAX)/R
      END DO
      DO A = 1, ND
        DTDP(A) = DTAU*TNEW(A)
        DO B = 1, ND
          IF (A .EQ. B) THEN
            DTDDU(A, B) = F*(1.0D0 - TNEW(A)*TNEW(B))
          ELSE
            DTDDU(A, B) = F*(0.0D0 - TNEW(A)*TNEW(B))
          END IF
        END DO
      END DO
      DO A = 1, ND
        TNEW(A) = TNEW(A)*TAU
      END DO
      RETURN
      END
C
"""


def core_source(constants, continuous, kt):
    """The law core: smooth minimum, Eqs. 24-25, stiffness, return map (fixed form)."""
    lines = _smin().splitlines() + ["C"] + _law(constants, continuous) + _kt(kt)
    return "\n".join(lines) + "\n" + _RMAP


_FRIC = """\
C=======================================================================
C     Abaqus/Standard user subroutine FRIC (documented argument list).
C     STATEV(1) = p_hist (DEPVAR >= 1), STATEV(2) = cached
C     -ln alpha1(p_hist) (DEPVAR >= 2, optional), STATEV(3) = status of
C     the last call,
C     0 open 1 stick 2 slip (DEPVAR >= 3, optional, output only).
C     Abaqus passes STATEV and TAU as at the start of the increment and
C     keeps the values written here only when the increment converges:
C     p_hist therefore rises only through Abaqus' commit.
C     PROPS are not used (NPROPS may be 0).
C=======================================================================
      SUBROUTINE FRIC(LM,TAU,DDTDDG,DDTDDP,DSLIP,SED,SFD,
     1 DDTDDT,PNEWDT,STATEV,DGAM,TAULM,PRESS,DPRESS,DDPDDH,SLIP,
     2 KSTEP,KINC,TIME,DTIME,NOEL,CINAME,SLNAME,MSNAME,NPT,NODE,
     3 NPATCH,COORDS,RCOORD,DROT,TEMP,PREDEF,NFDIR,MCRD,NPRED,
     4 NSTATV,CHRLNGTH,PROPS,NPROPS)
C
      INCLUDE 'ABA_PARAM.INC'
C
      CHARACTER*80 CINAME,SLNAME,MSNAME
C
      DIMENSION TAU(NFDIR),DDTDDG(NFDIR,NFDIR),DDTDDP(NFDIR),
     1 DSLIP(NFDIR),DDTDDT(NFDIR,2),STATEV(*),DGAM(NFDIR),
     2 TAULM(NFDIR),SLIP(NFDIR),TIME(2),COORDS(MCRD),
     3 RCOORD(MCRD),DROT(2,2),TEMP(2),PREDEF(2,*),PROPS(NPROPS)
C
      DOUBLE PRECISION P, PH, G1H, G1NEW, TLIM, DTAU, XKT, KFALL
      DOUBLE PRECISION TOLD(2), TNEW(2), DTDDU(2,2), DTDP(2)
      INTEGER ISTAT, IA, IB
      DOUBLE PRECISION SBMF_KT
      EXTERNAL SBMF_KT
C     elastic slip of Abaqus' own penalty friction: 0.005 CHRLNGTH
      DOUBLE PRECISION FSLIP
      PARAMETER (FSLIP = 5.0D-3)
C
      P = PRESS
      PH = STATEV(1)
      G1H = -1.0D0
      IF (NSTATV .GE. 2) G1H = STATEV(2)
      SED = 0.0D0
      SFD = 0.0D0
      DO IA = 1, NFDIR
        DSLIP(IA) = 0.0D0
        DDTDDP(IA) = 0.0D0
        DDTDDT(IA, 1) = 0.0D0
        DDTDDT(IA, 2) = 0.0D0
        DO IB = 1, NFDIR
          DDTDDG(IA, IB) = 0.0D0
        END DO
      END DO
      IF (.NOT. (P .GT. 0.0D0)) THEN
C       open (no pressure): no friction, history unchanged
        LM = 2
        DO IA = 1, NFDIR
          TAU(IA) = 0.0D0
        END DO
        IF (NSTATV .GE. 3) STATEV(3) = 0.0D0
        RETURN
      END IF
      CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
      KFALL = MAX(TLIM, TINY(1.0D0))/(FSLIP*CHRLNGTH)
      XKT = SBMF_KT(P, KFALL)
      DO IA = 1, NFDIR
        TOLD(IA) = TAU(IA)
      END DO
      CALL SBMF_RMAP(NFDIR, TLIM, DTAU, DGAM, TOLD, XKT, TNEW, DTDDU,
     &               DTDP, ISTAT)
      LM = 0
      DO IA = 1, NFDIR
        TAU(IA) = TNEW(IA)
        DDTDDP(IA) = DTDP(IA)
        DO IB = 1, NFDIR
          DDTDDG(IA, IB) = DTDDU(IA, IB)
        END DO
        IF (ISTAT .EQ. 2) THEN
          DSLIP(IA) = DGAM(IA) - (TNEW(IA) - TOLD(IA))/XKT
        END IF
        SED = SED + 0.5D0*TNEW(IA)*TNEW(IA)/XKT
        SFD = SFD + TNEW(IA)*DSLIP(IA)
      END DO
C     trial history max(p_hist, p): kept by Abaqus only if converged
      STATEV(1) = MAX(PH, P)
      IF (NSTATV .GE. 2) STATEV(2) = G1NEW
      IF (NSTATV .GE. 3) STATEV(3) = DBLE(ISTAT)
      RETURN
      END
"""

_VFRIC = """\
C=======================================================================
C     Abaqus/Explicit user subroutine VFRIC (documented argument list).
C     statev(1,n) = p_hist of secondary (slave) node n, statev(2,n) =
C     cached -ln alpha1(p_hist) (optional), statev(3,n) = last status
C     (optional). Explicit has no iterations: each increment commits.
C     p = fNormal/areaSec; the force limit tau(p, p_hist) areaSec;
C     stick when tau > 0 and the stick force is within it, otherwise
C     slip (tau = 0: no force, status slip, as traction_update).
C=======================================================================
      subroutine vfric(
C Write only -
     1 fTangential,
C Read/Write -
     2 statev,
C Read only -
     3 kStep, kInc, nContact, nFacNod, nSecNod, nMainNod,
     4 nFricDir, nDir, nStateVar, nProps, nTemp, nPred, numDefTfv,
     5 jSecUid, jMainUid, jConSecid, jConMainid, timStep, timGlb,
     6 dTimCur, surfInt, surfSec, surfMain, lContType,
     7 dSlipFric, fStickForce, fTangPrev, fNormal, frictionWork,
     8 shape, coordSec, coordMain, dirCosSl, dirCosN, props,
     9 areaSec, tempSec, preDefSec, tempMain, preDefMain)
C
      include 'vaba_param.inc'
C
      character*80 surfInt, surfSec, surfMain
C
      dimension props(nProps), statev(nStateVar,nSecNod),
     1 dSlipFric(nDir,nContact),
     2 fTangential(nFricDir,nContact),
     3 fTangPrev(nDir,nContact),
     4 fStickForce(nContact), areaSec(nSecNod),
     5 fNormal(nContact), shape(nFacNod,nContact),
     6 coordSec(nDir,nSecNod), coordMain(nDir,nMainNod),
     7 dirCosSl(nDir,nContact), dirCosN(nDir,nContact),
     8 jSecUid(nSecNod), jMainUid(nMainNod),
     9 jConSecid(nContact), jConMainid(nFacNod,nContact),
     1 tempSec(nContact), preDefSec(nContact,nPred),
     2 tempMain(numDefTfv), preDefMain(numDefTfv,nPred)
C
      double precision p, ph, g1h, g1new, tlim, dtau, flim
      integer k, n, ia, istat
C
      do k = 1, nContact
        n = jConSecid(k)
        do ia = 1, nFricDir
          fTangential(ia, k) = 0.0d0
        end do
C       an overflowing pressure is taken as the largest double
        p = min(fNormal(k)/areaSec(n), huge(p))
        ph = statev(1, n)
        g1h = -1.0d0
        if (nStateVar .ge. 2) g1h = statev(2, n)
        if (.not. (p .gt. 0.0d0)) then
          if (nStateVar .ge. 3) statev(3, n) = 0.0d0
        else
          call SBMF_SHEAR(p, ph, g1h, tlim, dtau, g1new)
          flim = tlim*areaSec(n)
          if (tlim .gt. 0.0d0 .and. fStickForce(k) .le. flim) then
            fTangential(1, k) = -fStickForce(k)
            istat = 1
          else
            fTangential(1, k) = -flim
            istat = 2
          end if
          statev(1, n) = max(ph, p)
          if (nStateVar .ge. 2) statev(2, n) = g1new
          if (nStateVar .ge. 3) statev(3, n) = dble(istat)
        end if
      end do
      return
      end
"""

_GENERIC = """\
C=======================================================================
C     Host-neutral entry point, to be called from the host's friction
C     template (see the README): one contact point per call.
C     In:  ND (1 or 2 tangential directions), P (contact pressure),
C          PH (committed p_hist), G1H (committed cache -ln alpha1(PH),
C          or <= 0: recompute),
C          DU(ND) (slip increment since the last converged state),
C          TOLD(ND) (traction of the last converged state),
C          KHOST (the host's tangential penalty, used only when the
C          parameter file has no calibrated k_t and no --k-t was given).
C     Out: TNEW(ND), DTDDU(ND,ND), DTDP(ND), ISTAT (0 open, 1 stick,
C          2 slip), PHNEW, G1NEW: the trial state; the caller stores
C          it only when the host accepts (converges) the increment.
C=======================================================================
      SUBROUTINE SBMF_FRICTION(ND, P, PH, G1H, DU, TOLD, KHOST, TNEW,
     &                         DTDDU, DTDP, ISTAT, PHNEW, G1NEW)
      IMPLICIT NONE
      INTEGER ND, ISTAT, A, B
      DOUBLE PRECISION P, PH, G1H, DU(ND), TOLD(ND), KHOST, TNEW(ND)
      DOUBLE PRECISION DTDDU(ND, ND), DTDP(ND), PHNEW, G1NEW
      DOUBLE PRECISION TLIM, DTAU, XKT
      DOUBLE PRECISION SBMF_KT
      EXTERNAL SBMF_KT
      IF (.NOT. (P .GT. 0.0D0)) THEN
        DO A = 1, ND
          TNEW(A) = 0.0D0
          DTDP(A) = 0.0D0
          DO B = 1, ND
            DTDDU(A, B) = 0.0D0
          END DO
        END DO
        ISTAT = 0
        PHNEW = PH
        G1NEW = G1H
        RETURN
      END IF
      CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
      XKT = SBMF_KT(P, KHOST)
      CALL SBMF_RMAP(ND, TLIM, DTAU, DU, TOLD, XKT, TNEW, DTDDU, DTDP,
     &               ISTAT)
      PHNEW = MAX(PH, P)
      RETURN
      END
"""


def _assemble(header, body, constants, continuous, kt):
    return _check_fixed_form(header + body + "C\n" + core_source(constants, continuous, kt))


def fric_source(header, constants, continuous, kt):
    """Abaqus/Standard ``FRIC`` with the core appended."""
    return _assemble(header, _FRIC, constants, continuous, kt)


def vfric_source(header, constants, continuous, kt):
    """Abaqus/Explicit ``VFRIC`` with the core appended."""
    return _assemble(header, _VFRIC, constants, continuous, kt)


def generic_source(header, constants, continuous, kt):
    """The host-neutral ``SBMF_FRICTION`` entry with the core appended (LS-DYNA, ANSYS)."""
    return _assemble(header, _GENERIC, constants, continuous, kt)


_VFRICTION = """\
C=======================================================================
C     Abaqus/Explicit user subroutine VFRICTION (general contact;
C     argument list of the Abaqus User Subroutines Reference). One call
C     per block of nBlock contact points. state(i, j, k): variable i of
C     state node j of contact point k (nNodState = 1 for node-type
C     secondary surfaces, > 1 for edge-type ones):
C       1 = p_hist, 2 = cached -ln alpha1(p_hist) (optional), 3 = status
C       of the last call (optional). p = fNormal/areaCont. The contact
C     point's p_hist is the largest of its state nodes'; each state node
C     keeps max(its p_hist, p). Force limit tau(p, p_hist) areaCont;
C     stick when tau > 0 and the stick force is within it, otherwise
C     slip (tau = 0: no force, status slip, as traction_update).
C     Explicit has no iterations: each increment commits.
C=======================================================================
      subroutine vfriction(
C Write only -
     1 fTangential,
C Read/Write -
     2 state,
C Read only -
     3 nBlock, nBlockAnal, nBlockEdge,
     4 nNodState, nNodSlv, nNodMst,
     5 nFricDir, nDir,
     6 nStates, nProps, nTemp, nFields,
     7 jFlags, rData,
     8 surfInt, surfSlv, surfMst,
     9 jConSlvUid, jConMstUid, props,
     1 dSlipFric, fStickForce, fTangPrev, fNormal,
     2 areaCont, dircosN, dircosSl,
     3 shapeSlv, shapeMst,
     4 coordSlv, coordMst,
     5 velSlv, velMst,
     6 tempSlv, tempMst,
     7 fieldSlv, fieldMst)
C
      include 'vaba_param.inc'
C
      dimension fTangential(nFricDir,nBlock),
     1 state(nStates,nNodState,nBlock),
     2 jConSlvUid(nNodSlv,nBlock),
     3 jConMstUid(nNodMst,nBlockAnal),
     4 props(nProps),
     5 dSlipFric(nDir,nBlock),
     6 fStickForce(nBlock),
     7 fTangPrev(nDir,nBlock),
     8 fNormal(nBlock),
     9 areaCont(nBlock),
     1 dircosN(nDir,nBlock),
     2 dircosSl(nDir,nBlock),
     3 shapeSlv(nNodSlv,nBlockEdge),
     4 shapeMst(nNodMst,nBlockAnal),
     5 coordSlv(nDir,nNodSlv,nBlock),
     6 coordMst(nDir,nNodMst,nBlockAnal),
     7 velSlv(nDir,nNodSlv,nBlock),
     8 velMst(nDir,nNodMst,nBlockAnal),
     9 tempSlv(nBlock),
     1 tempMst(nBlockAnal),
     2 fieldSlv(nFields,nBlock),
     3 fieldMst(nFields,nBlockAnal)
      dimension jFlags(*), rData(*)
      character*80 surfInt, surfSlv, surfMst
C
      double precision p, ph, g1h, g1new, tlim, dtau, flim, phnew, sj
      integer k, j, ia, istat, jmax
C
      do k = 1, nBlock
        do ia = 1, nFricDir
          fTangential(ia, k) = 0.0d0
        end do
        p = 0.0d0
C       an overflowing pressure is taken as the largest double
        if (areaCont(k) .gt. 0.0d0) then
          p = min(fNormal(k)/areaCont(k), huge(p))
        end if
        if (.not. (p .gt. 0.0d0)) then
C         open (or no area): no friction, history unchanged
          if (nStates .ge. 3) then
            do j = 1, nNodState
              state(3, j, k) = 0.0d0
            end do
          end if
        else
          ph = 0.0d0
          jmax = 1
          do j = 1, nNodState
            if (state(1, j, k) .gt. ph) then
              ph = state(1, j, k)
              jmax = j
            end if
          end do
          g1h = -1.0d0
          if (nStates .ge. 2) g1h = state(2, jmax, k)
          call SBMF_SHEAR(p, ph, g1h, tlim, dtau, g1new)
          flim = tlim*areaCont(k)
          if (tlim .gt. 0.0d0 .and. fStickForce(k) .le. flim) then
            fTangential(1, k) = -fStickForce(k)
            istat = 1
          else
            fTangential(1, k) = -flim
            istat = 2
          end if
          phnew = max(ph, p)
          do j = 1, nNodState
            sj = max(state(1, j, k), 0.0d0)
            if (nStates .ge. 2) then
C             the cache belongs to phnew; a node raised to p < phnew
C             gets 0 ("recompute")
              if (max(sj, p) .eq. phnew) then
                state(2, j, k) = g1new
              else if (p .gt. sj) then
                state(2, j, k) = 0.0d0
              end if
            end if
            state(1, j, k) = max(sj, p)
            if (nStates .ge. 3) state(3, j, k) = dble(istat)
          end do
        end if
      end do
      return
      end
"""

_USRFRC_SMP = """\
C=======================================================================
C     LS-DYNA SMP user friction usrfrc (argument list and conventions
C     of the sample usrfrc in LSTC's user file dyn21.f). Called once
C     per cycle with the NIISV5 active slave nodes IISV5(:). All host
C     arguments have the host's default REAL/INTEGER (compile with the
C     host's flags: SP as is, DP with ifort -r8 -i8 or gfortran
C     -fdefault-real-8 -fdefault-double-8 -fdefault-integer-8); the
C     law is computed in double precision.
C     p = -FNI/AREAS (FNI < 0 in compression). Trial friction force:
C     tangential part of FDAT(3:5) (old friction force) + STFK SFACN3
C     (DX, DY, DZ) (k_t = STFK SFACN3/AREAS unless the export baked in
C     a calibrated k_t); return map of the law on tractions (force /
C     AREAS), as frictionlaw.traction_update_force; the new force is
C     stored in FDAT(3:5) and added to FXIS, FYIS, FZIS.
C     UFHIST(1, ILBSV(II)) = p_hist (NHV >= 1; stored rounded down to
C     the host REAL), UFHIST(2, .) = cache -ln alpha1(p_hist) (NHV >= 2,
C     used in double-precision hosts only), UFHIST(3, .) = status of
C     the last cycle 0 open 1 stick 2 slip (NHV >= 3).
C     FNI >= 0 or AREAS <= 0: open (no friction, FDAT(3:5) = 0,
C     history unchanged). The Coulomb coefficients FRIC1..4, FRC and
C     the thermal data are not used.
C=======================================================================
      SUBROUTINE USRFRC(NOSL,TIME,NCYCLE,DT2,INSV,AREAS,XS,YS,ZS,
     & LSV,IX1,IX2,IX3,IX4,AREAM,XX1,XX2,XX3,STFN,STF,FNI,
     & DX,DY,DZ,FDT2,NINPUT,UA,SIDE,IISV5,NIISV5,RN1,RN2,RN3,FRIC1,
     & FRIC2,FRIC3,FRIC4,BIGNUM,FDAT,ISEG,FXIS,FYIS,FZIS,SS,TT,
     & ILBSV,STFK,FRC,NUMNP,NPC,PLD,LCFST,LCFDT,TEMP,TEMP_BOT,
     & TEMP_TOP,ISURFACE,NHV,UFHIST,NEPS,UFEPS,SFACN3)
      IMPLICIT NONE
      INTEGER NOSL, NCYCLE, NINPUT, NIISV5, NUMNP, NHV, NEPS
      INTEGER INSV(*), LSV(*), IX1(*), IX2(*), IX3(*), IX4(*)
      INTEGER IISV5(*), ISEG(*), ILBSV(*), NPC(*), LCFST(*), LCFDT(*)
      INTEGER ISURFACE(*)
      REAL TIME, DT2, FDT2, FRIC1, FRIC2, FRIC3, FRIC4, BIGNUM, SFACN3
      REAL AREAS(*), XS(*), YS(*), ZS(*), AREAM(*), XX1(*), XX2(*)
      REAL XX3(*), STFN(*), STF(*), FNI(*), DX(*), DY(*), DZ(*), UA(*)
      REAL RN1(*), RN2(*), RN3(*), FDAT(5,*), FXIS(*), FYIS(*)
      REAL FZIS(*), SS(*), TT(*), STFK(*), FRC(2,*), PLD(2,*), TEMP(*)
      REAL TEMP_BOT(*), TEMP_TOP(*), UFHIST(NHV,*), UFEPS(*)
      CHARACTER*(*) SIDE
C
      INTEGER KK, II, IH, A, ISTAT
      DOUBLE PRECISION P, PH, PHNEW, G1H, G1NEW, TLIM, DTAU, AR, FN
      DOUBLE PRECISION RN(3), FO(3), D(3), Q, KT, HD, HR, F
      DOUBLE PRECISION TOLD(3), TNEW(3), DTDDU(3,3), DTDP(3)
      REAL RPH
      LOGICAL USECAC
      DOUBLE PRECISION SBMF_KT
      EXTERNAL SBMF_KT
C     largest double and largest host REAL
      HD = HUGE(HD)
      HR = DBLE(HUGE(RPH))
C     the cache is exact only where the host REAL is a double
      USECAC = (KIND(RPH) .EQ. KIND(HD)) .AND. (NHV .GE. 2)
      DO KK = 1, NIISV5
        II = IISV5(KK)
        IH = ILBSV(II)
        ISEG(II) = LSV(II)
        FDAT(1, II) = SS(II)
        FDAT(2, II) = TT(II)
        AR = DBLE(AREAS(II))
        FN = -DBLE(FNI(II))
        IF (.NOT. (FN .GT. 0.0D0 .AND. AR .GT. 0.0D0)) THEN
          DO A = 3, 5
            FDAT(A, II) = 0.0
          END DO
          IF (NHV .GE. 3) UFHIST(3, IH) = 0.0
          CYCLE
        END IF
        P = MIN(FN/AR, HD)
        PH = 0.0D0
        IF (NHV .GE. 1) PH = MAX(DBLE(UFHIST(1, IH)), 0.0D0)
        G1H = -1.0D0
        IF (USECAC) G1H = DBLE(UFHIST(2, IH))
        RN(1) = DBLE(RN1(II))
        RN(2) = DBLE(RN2(II))
        RN(3) = DBLE(RN3(II))
        D(1) = DBLE(DX(II))
        D(2) = DBLE(DY(II))
        D(3) = DBLE(DZ(II))
        DO A = 1, 3
          FO(A) = DBLE(FDAT(2 + A, II))
        END DO
C       tangential parts: the normal components projected out
        Q = FO(1)*RN(1) + FO(2)*RN(2) + FO(3)*RN(3)
        DO A = 1, 3
          FO(A) = FO(A) - Q*RN(A)
        END DO
        Q = D(1)*RN(1) + D(2)*RN(2) + D(3)*RN(3)
        DO A = 1, 3
          D(A) = D(A) - Q*RN(A)
        END DO
C       tractions: t_old = F_old/A, k_t = STFK SFACN3/A (kept finite)
        KT = MAX(MIN((DBLE(STFK(II))*DBLE(SFACN3))/AR, HD), 0.0D0)
C       a calibrated k_t (table or --k-t) replaces the penalty's
        KT = SBMF_KT(P, KT)
        DO A = 1, 3
          TOLD(A) = MAX(MIN(FO(A)/AR, HD), -HD)
        END DO
        CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
        CALL SBMF_RMAP(3, TLIM, DTAU, D, TOLD, KT, TNEW, DTDDU, DTDP,
     &                 ISTAT)
        DO A = 1, 3
          F = MAX(MIN(TNEW(A)*AR, HR), -HR)
          FDAT(2 + A, II) = REAL(F)
        END DO
        FXIS(II) = FXIS(II) + FDAT(3, II)
        FYIS(II) = FYIS(II) + FDAT(4, II)
        FZIS(II) = FZIS(II) + FDAT(5, II)
        PHNEW = MAX(PH, P)
        IF (NHV .GE. 1) THEN
C         stored rounded down: a constant pressure stays on Eq. 24
          RPH = REAL(MIN(PHNEW, HR))
          IF (DBLE(RPH) .GT. PHNEW) RPH = NEAREST(RPH, -1.0)
          UFHIST(1, IH) = RPH
        END IF
        IF (USECAC) THEN
          UFHIST(2, IH) = REAL(G1NEW)
        ELSE IF (NHV .GE. 2) THEN
          UFHIST(2, IH) = 0.0
        END IF
        IF (NHV .GE. 3) UFHIST(3, IH) = REAL(ISTAT)
      END DO
      RETURN
      END
"""

_USRFRC_MPP = """\
C=======================================================================
C     LS-DYNA MPP user friction usrfrc (argument list of the MPP sample
C     in LSTC's user file dyn21.F): one slave node per call, returns
C     friction coefficients. Coefficient form of the law: FSTT = FDYN =
C     tau(p, p_hist)/p with p = PRS (interface pressure, > 0 in
C     contact); LS-DYNA applies them in its own Coulomb return map.
C     UH(1) = p_hist (NH >= 1; stored rounded down to the host REAL),
C     UH(2) = cache -ln alpha1(p_hist) (NH >= 2, double hosts only).
C     PRS <= 0: FSTT = FDYN = 0, history unchanged. Host arguments have
C     the host's default REAL/INTEGER (see the SMP routine).
C=======================================================================
      SUBROUTINE USRFRC(FSTT,FDYN,UC,NC,PRS,TEMP,V,UH,NH,CRV,NNPCRV,
     & NOSL,ICTYPE,SIDE,TIME,NCYCLE,DT2,FRIC1,FRIC2,FRIC3,FRIC4,LSV,
     & IDELE8,SFAC1,SFAC2,INSV,FNI,AREAS,STFK,IX1,IX2,IX3,IX4,AREAM,
     & RN1,RN2,RN3,UE,NE)
      IMPLICIT NONE
      REAL FSTT, FDYN
      INTEGER NC, NH, NOSL, ICTYPE, NCYCLE, LSV, INSV, NE
      INTEGER IX1, IX2, IX3, IX4
      REAL UC(*), UH(*), UE(*), CRV(*)
      REAL PRS, TEMP, V, TIME, DT2, FRIC1, FRIC2, FRIC3, FRIC4
      REAL SFAC1, SFAC2, FNI, AREAS, STFK, AREAM, RN1, RN2, RN3
      INTEGER NNPCRV(*)
      CHARACTER*(*) SIDE
      INTEGER*8 IDELE8
C
      DOUBLE PRECISION P, PH, PHNEW, G1H, G1NEW, TLIM, DTAU, XMU, HR
      REAL RPH
      LOGICAL USECAC
      HR = DBLE(HUGE(RPH))
      USECAC = (KIND(RPH) .EQ. KIND(HR)) .AND. (NH .GE. 2)
      P = DBLE(PRS)
      IF (.NOT. (P .GT. 0.0D0)) THEN
        FSTT = 0.0
        FDYN = 0.0
        RETURN
      END IF
      PH = 0.0D0
      IF (NH .GE. 1) PH = MAX(DBLE(UH(1)), 0.0D0)
      G1H = -1.0D0
      IF (USECAC) G1H = DBLE(UH(2))
      CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
      XMU = MIN(TLIM/P, HR)
      FSTT = REAL(XMU)
      FDYN = FSTT
      PHNEW = MAX(PH, P)
      IF (NH .GE. 1) THEN
        RPH = REAL(MIN(PHNEW, HR))
        IF (DBLE(RPH) .GT. PHNEW) RPH = NEAREST(RPH, -1.0)
        UH(1) = RPH
      END IF
      IF (USECAC) UH(2) = REAL(G1NEW)
      RETURN
      END
"""


def vfriction_source(header, constants, continuous, kt):
    """Abaqus/Explicit ``VFRICTION`` (general contact) with the core appended."""
    return _assemble(header, _VFRICTION, constants, continuous, kt)


def usrfrc_smp_source(header, constants, continuous, kt):
    """LS-DYNA SMP ``usrfrc`` (force return map, history in ``ufhist``) with the core."""
    return _assemble(header, _USRFRC_SMP, constants, continuous, kt)


def usrfrc_mpp_source(header, constants, continuous, kt):
    """LS-DYNA MPP ``usrfrc`` (coefficient form, history in ``uh``) with the core."""
    return _assemble(header, _USRFRC_MPP, constants, continuous, kt)
