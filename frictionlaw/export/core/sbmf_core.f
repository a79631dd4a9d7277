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
{% for L in laws %}
{% with zp=L.prefix, law=L.law, continuous=L.continuous, first=L.first, reload=L.reload, kt=L.kt, ln_h=L.ln_h %}
{% include "core/sbmf_law.f" %}
{% endwith %}
{% endfor %}
{% if zones %}
{% include "core/sbmf_zones.f" %}
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
