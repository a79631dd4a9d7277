{#
  The law core of every generated Fortran routine (fixed form, IMPLICIT NONE, double
  precision), included at the end of each host's entry template. It follows
  frictionlaw._kernels statement by statement (smooth_min_log, log_product,
  sbmf_first_scalar or, for the tabulated first loading, the routines of the template its
  record names (core/sbmf_first_table.f), sbmf_reload_scalar or, for the tabulated reload
  form, the routines of core/sbmf_reload_table.f, traction_row), so that the compiled routine
  and the runtime agree to rounding. Rendered with the values of
  frictionlaw.export._law.core_context: law (TMAX, H, C1, XN1, C2, XN2 in the host's units),
  continuous (continuous_reload), first (the first-loading form's FirstSpec: its knots and
  slopes as PARAMETER arrays; None for Eq. 24), reload (the tabulated form's ReloadSpec: its
  knots and slopes as PARAMETER arrays, no DATA or SAVE; None for the paper's Eq. 25), kt
  (the StiffnessSpec), ln_small, ln_sat (the smooth minimum's
  branch points), ln_d_max (the tabulated form's bound on ln dtau/dp where it is formed in
  logs), ln_h (ln H in the host's unit). A new law form changes this file (or the one it
  includes) and core_context, nothing per target. At its end core/sbmf_guards.f (the guards'
  once-per-process flags and messages; context guard_text).
#}
{% macro libm(name) %}
      DOUBLE PRECISION FUNCTION SBMF_{{ name | upper }}(Z)
      USE, INTRINSIC :: ISO_C_BINDING
      IMPLICIT NONE
      DOUBLE PRECISION Z
      INTERFACE
        FUNCTION C_{{ name | upper }}(A) BIND(C, NAME='{{ name }}')
          IMPORT :: C_DOUBLE
          REAL(C_DOUBLE), VALUE :: A
          REAL(C_DOUBLE) :: C_{{ name | upper }}
        END FUNCTION C_{{ name | upper }}
      END INTERFACE
      SBMF_{{ name | upper }} = C_{{ name | upper }}(Z)
      RETURN
      END
{%- endmacro %}
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
      PARAMETER (LNYSML = {{ ln_small | double }})
      PARAMETER (LNYSAT = {{ ln_sat | double }})
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
      PARAMETER (LNYSML = {{ ln_small | double }})
      PARAMETER (LNYSAT = {{ ln_sat | double }})
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
{{ libm("expm1") }}
C
{{ libm("log1p") }}
C
{% if first %}
{% include first.template %}
{% else %}
C=======================================================================
C     Eq. 24 (frictionlaw's sbmf_first_scalar): TAU = TMAX g(P C1/H;
C     n1), DTAU = dTAU/dP; G1 = the cache value for p_hist = P,
C     -ln alpha1(P).
C=======================================================================
      SUBROUTINE SBMF_FIRST(P, TAU, DTAU, G1)
      IMPLICIT NONE
      DOUBLE PRECISION P, TAU, DTAU, G1
      DOUBLE PRECISION LNX1, X1, G, GOX, DG, GL
      DOUBLE PRECISION SBMF_LPROD
      EXTERNAL SBMF_LPROD
      DOUBLE PRECISION TMAX, H, C1, XN1, C1H
      PARAMETER (TMAX = {{ law.TMAX | double }})
      PARAMETER (H = {{ law.H | double }})
      PARAMETER (C1 = {{ law.C1 | double }})
      PARAMETER (XN1 = {{ law.XN1 | double }})
      PARAMETER (C1H = C1/H)
      LNX1 = SBMF_LPROD(P, C1H)
      X1 = P*C1H
      IF (.NOT. (1.0D-300 .LT. X1 .AND. X1 .LT. 1.0D+300)) X1 = 0.0D0
      CALL SBMF_SMIN(LNX1, X1, XN1, G, GOX, DG, GL)
      IF (LNX1 .LT. 0.0D0) THEN
        TAU = P*(TMAX*C1H)*GOX
      ELSE
        TAU = TMAX*G
      END IF
      TAU = MIN(TAU, TMAX)
      DTAU = TMAX*C1H*DG
      G1 = -GL
      RETURN
      END
C
{% endif %}
{% if reload %}
{% include "core/sbmf_reload_table.f" %}
{% else %}
C=======================================================================
C     Eq. 25 below p_hist (frictionlaw's sbmf_reload_scalar):
C     TAU = TMAX a1h g(x2; n2), a1h = alpha1(PH) of the first loading
C     that runs, x2 = P C2/(H a1h),
{% if continuous %}
C     all formed in logs (a1h -> 0 cannot overflow). Continuous
C     variant: divided by g(x2(PH); n2) to meet the first loading at
C     PH.
{% else %}
C     all formed in logs (a1h -> 0 cannot overflow).
{% endif %}
C     Cap TMAX a1h for P <= PH, TMAX above. G1H: cached -ln a1h
C     (<= 0: recompute it); G1OUT: the cache value for PH.
C=======================================================================
      SUBROUTINE SBMF_RELOAD(P, PH, G1H, TAU, DTAU, G1OUT)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT
      DOUBLE PRECISION LNA1H, A1H, LNX2, X2, G2, GOX2, DG2, LG2, CAP
{% if continuous %}
      DOUBLE PRECISION LNX2H, LG2H, SCL
{% endif %}
{% if first %}
      DOUBLE PRECISION SBMF_LPROD, SBMF_LNA1
      EXTERNAL SBMF_LPROD, SBMF_LNA1
{% if continuous %}
      DOUBLE PRECISION SBMF_SMINL
      EXTERNAL SBMF_SMINL
{% endif %}
      DOUBLE PRECISION TMAX, H, C2, XN2, C2H
{% else %}
      DOUBLE PRECISION SBMF_LPROD, SBMF_SMINL
      EXTERNAL SBMF_LPROD, SBMF_SMINL
      DOUBLE PRECISION TMAX, H, C1, XN1, C2, XN2, C1H, C2H
{% endif %}
      PARAMETER (TMAX = {{ law.TMAX | double }})
      PARAMETER (H = {{ law.H | double }})
{% if not first %}
      PARAMETER (C1 = {{ law.C1 | double }})
      PARAMETER (XN1 = {{ law.XN1 | double }})
{% endif %}
      PARAMETER (C2 = {{ law.C2 | double }})
      PARAMETER (XN2 = {{ law.XN2 | double }})
{% if not first %}
      PARAMETER (C1H = C1/H)
{% endif %}
      PARAMETER (C2H = C2/H)
      G1OUT = G1H
      IF (.NOT. (P .GT. 0.0D0 .AND. PH .GT. 0.0D0)) THEN
        TAU = 0.0D0
        DTAU = 0.0D0
        RETURN
      END IF
      IF (G1H .GT. 0.0D0) THEN
        LNA1H = -G1H
      ELSE
{% if first %}
        LNA1H = SBMF_LNA1(PH)
{% else %}
        LNA1H = SBMF_SMINL(SBMF_LPROD(PH, C1H), XN1)
{% endif %}
        G1OUT = -LNA1H
      END IF
      LNX2 = SBMF_LPROD(P, C2H) - LNA1H
      A1H = EXP(LNA1H)
C     x2 as a product where it is a normal double (saves an exp)
      X2 = P*C2H
      IF (1.0D-300 .LT. X2 .AND. X2 .LT. 1.0D+300 .AND.
     &    A1H .GT. 1.0D-300) THEN
        X2 = X2/A1H
        IF (.NOT. (X2 .LT. 1.0D+300)) X2 = 0.0D0
      ELSE
        X2 = 0.0D0
      END IF
      CALL SBMF_SMIN(LNX2, X2, XN2, G2, GOX2, DG2, LG2)
{% if continuous %}
C     continuous_reload: divided by g(x2(PH); n2), formed in logs
      LNX2H = SBMF_LPROD(PH, C2H) - LNA1H
      LG2H = SBMF_SMINL(LNX2H, XN2)
      SCL = EXP(-LG2H)
      TAU = TMAX*EXP(LNA1H + LG2 - LG2H)
      DTAU = TMAX*C2H*DG2*SCL
{% else %}
      IF (LNX2 .LT. 0.0D0) THEN
C       alpha1(PH) cancels
        TAU = P*(TMAX*C2H)*GOX2
      ELSE
        TAU = TMAX*A1H*G2
      END IF
      DTAU = TMAX*C2H*DG2
{% endif %}
      IF (P .LE. PH) THEN
        CAP = TMAX*A1H
      ELSE
        CAP = TMAX
      END IF
      IF (TAU .GE. CAP) THEN
        TAU = CAP
        IF (P .GT. PH) DTAU = 0.0D0
      END IF
      RETURN
      END
C
{% endif %}
C=======================================================================
C     Shear limit (Eqs. 24-26): Eq. 25 while P < PH, else the first
C     loading (SBMF_FIRST: Eq. 24 or the tabulated first loading);
C     P <= 0 gives 0. G1OUT: the cache value for max(PH, P).
C=======================================================================
      SUBROUTINE SBMF_SHEAR(P, PH, G1H, TAU, DTAU, G1OUT)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT
      G1OUT = G1H
      IF (.NOT. (P .GT. 0.0D0)) THEN
        TAU = 0.0D0
        DTAU = 0.0D0
        RETURN
      END IF
      IF (P .LT. PH) THEN
        CALL SBMF_RELOAD(P, PH, G1H, TAU, DTAU, G1OUT)
      ELSE
        CALL SBMF_FIRST(P, TAU, DTAU, G1OUT)
      END IF
      RETURN
      END
C
C=======================================================================
C     Tangential stick stiffness k_t at pressure P (stress/length).
{% if kt.kind == "table" %}
C     Calibrated table k_t(p): log-log interpolation, constant beyond
C     the end points (as frictionlaw.TangentialStiffness).
C=======================================================================
      DOUBLE PRECISION FUNCTION SBMF_KT(P, KFALL)
      IMPLICIT NONE
      DOUBLE PRECISION P, KFALL, LP, W
      INTEGER NKT, J
      PARAMETER (NKT = {{ kt.log_p | length }})
      DOUBLE PRECISION LPT(NKT), LKT(NKT), PLO, PHI, KLO, KHI
      PARAMETER (PLO = {{ kt.p[0] | double }})
      PARAMETER (PHI = {{ kt.p[-1] | double }})
      PARAMETER (KLO = {{ kt.k[0] | double }})
      PARAMETER (KHI = {{ kt.k[-1] | double }})
      PARAMETER (LPT = (/
     &  {{ kt.log_p | map("double") | join(",
     &  ") }} /))
      PARAMETER (LKT = (/
     &  {{ kt.log_k | map("double") | join(",
     &  ") }} /))
      IF (KFALL .LT. 0.0D0) CONTINUE
      IF (.NOT. (P .GT. PLO)) THEN
        SBMF_KT = KLO
        RETURN
      END IF
      IF (.NOT. (P .LT. PHI)) THEN
        SBMF_KT = KHI
        RETURN
      END IF
      LP = LOG(P)
      J = 1
   10 IF (J .LT. NKT - 1 .AND. LP .GE. LPT(J + 1)) THEN
        J = J + 1
        GOTO 10
      END IF
      W = (LKT(J + 1) - LKT(J))/(LPT(J + 1) - LPT(J))
      SBMF_KT = EXP(W*(LP - LPT(J)) + LKT(J))
      RETURN
      END
C
{% elif kt.kind == "constant" %}
C     Constant value given at export time (--k-t).
C=======================================================================
      DOUBLE PRECISION FUNCTION SBMF_KT(P, KFALL)
      IMPLICIT NONE
      DOUBLE PRECISION P, KFALL
      IF (P .LT. 0.0D0 .AND. KFALL .LT. 0.0D0) CONTINUE
      SBMF_KT = {{ kt.value | double }}
      RETURN
      END
C
{% else %}
C     No calibrated k_t in the parameter file: the host's KFALL.
C=======================================================================
      DOUBLE PRECISION FUNCTION SBMF_KT(P, KFALL)
      IMPLICIT NONE
      DOUBLE PRECISION P, KFALL
      IF (P .LT. 0.0D0) CONTINUE
      SBMF_KT = KFALL
      RETURN
      END
C
{% endif %}
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
{% include "core/sbmf_guards.f" %}
