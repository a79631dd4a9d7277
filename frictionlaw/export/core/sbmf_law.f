{#
  The law of one parameter file (one zone, or the one law of an export), included by
  core/sbmf_core.f once per law: the first loading (Eq. 24 or the template its form's record
  names, core/sbmf_first_table.f), the reload branch (Eq. 25 or core/sbmf_reload_table.f), the
  branch selection and the stick stiffness, each routine named with the law's prefix zp
  (SBMF_ for an export's one law: SBMF_FIRST, SBMF_RELOAD, SBMF_SHEAR, SBMF_KT; SZ01_, SZ02_,
  ... for the laws of a zoned export, which core/sbmf_zones.f chooses from). Context (the law's
  CoreLaw, frictionlaw.export._law): zp, law, continuous, first, reload, kt, ln_h, flat (the
  flattening block's FlatSpec: core/sbmf_flat.f follows; None without one); and the shared
  ln_small, ln_sat, ln_d_max, ln_q_start.
#}
{% if first %}
{% include first.template %}
{% else %}
C=======================================================================
C     Eq. 24 (frictionlaw's sbmf_first_scalar): TAU = TMAX g(P C1/H;
C     n1), DTAU = dTAU/dP; G1 = the cache value for p_hist = P,
C     -ln alpha1(P).
C=======================================================================
      SUBROUTINE {{ zp }}FIRST(P, TAU, DTAU, G1)
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
      SUBROUTINE {{ zp }}RELOAD(P, PH, G1H, TAU, DTAU, G1OUT)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT
      DOUBLE PRECISION LNA1H, A1H, LNX2, X2, G2, GOX2, DG2, LG2, CAP
{% if continuous %}
      DOUBLE PRECISION LNX2H, LG2H, SCL
{% endif %}
{% if first %}
      DOUBLE PRECISION SBMF_LPROD, {{ zp }}LNA1
      EXTERNAL SBMF_LPROD, {{ zp }}LNA1
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
        LNA1H = {{ zp }}LNA1(PH)
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
C     loading ({{ zp }}FIRST: Eq. 24 or the tabulated first loading);
C     P <= 0 gives 0. G1OUT: the cache value for max(PH, P).
C=======================================================================
      SUBROUTINE {{ zp }}SHEAR(P, PH, G1H, TAU, DTAU, G1OUT)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT
      G1OUT = G1H
      IF (.NOT. (P .GT. 0.0D0)) THEN
        TAU = 0.0D0
        DTAU = 0.0D0
        RETURN
      END IF
      IF (P .LT. PH) THEN
        CALL {{ zp }}RELOAD(P, PH, G1H, TAU, DTAU, G1OUT)
      ELSE
        CALL {{ zp }}FIRST(P, TAU, DTAU, G1OUT)
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
      DOUBLE PRECISION FUNCTION {{ zp }}KT(P, KFALL)
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
        {{ zp }}KT = KLO
        RETURN
      END IF
      IF (.NOT. (P .LT. PHI)) THEN
        {{ zp }}KT = KHI
        RETURN
      END IF
      LP = LOG(P)
      J = 1
   10 IF (J .LT. NKT - 1 .AND. LP .GE. LPT(J + 1)) THEN
        J = J + 1
        GOTO 10
      END IF
      W = (LKT(J + 1) - LKT(J))/(LPT(J + 1) - LPT(J))
      {{ zp }}KT = EXP(W*(LP - LPT(J)) + LKT(J))
      RETURN
      END
C
{% elif kt.kind == "constant" %}
C     Constant value given at export time (--k-t).
C=======================================================================
      DOUBLE PRECISION FUNCTION {{ zp }}KT(P, KFALL)
      IMPLICIT NONE
      DOUBLE PRECISION P, KFALL
      IF (P .LT. 0.0D0 .AND. KFALL .LT. 0.0D0) CONTINUE
      {{ zp }}KT = {{ kt.value | double }}
      RETURN
      END
C
{% else %}
C     No calibrated k_t in the parameter file: the host's KFALL.
C=======================================================================
      DOUBLE PRECISION FUNCTION {{ zp }}KT(P, KFALL)
      IMPLICIT NONE
      DOUBLE PRECISION P, KFALL
      IF (P .LT. 0.0D0) CONTINUE
      {{ zp }}KT = KFALL
      RETURN
      END
C
{% endif %}
{% if flat and target.form.bulk_strain %}
{% include "core/sbmf_flat.f" %}
{% endif %}
