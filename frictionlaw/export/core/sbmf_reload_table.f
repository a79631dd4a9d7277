{#
  The tabulated reload form's part of the law core (frictionlaw.reload_form), included by
  core/sbmf_core.f in place of the paper form's {{ zp }}RELOAD when the parameter file selects
  reload_form = "tabulated": {{ zp }}SMINS (frictionlaw._kernels.smooth_min_log_slope),
  {{ zp }}RTAB (reload_table_at) and {{ zp }}RELOAD (sbmf_reload_table_scalar), statement by
  statement. Rendered with core/sbmf_core.f's values (frictionlaw.export._law.core_context):
  law, continuous, reload (the ReloadSpec: knots and slopes as PARAMETER arrays), first (None:
  Eq. 24's alpha1(p_hist); else {{ zp }}LNA1 of the first-loading template), ln_small, ln_sat,
  ln_d_max, ln_h.
#}
C=======================================================================
C     ln G and the logarithmic slope SL = X dG/dX / G = 2Y/sinh(2Y) of
C     the smooth minimum from XL = ln X (frictionlaw's
C     smooth_min_log_slope): SBMF_SMIN's GL and its factor S (dG/dX =
C     G/X S), by the same statements, without G, G/X or dG/dX (one or
C     two exps less). Series branch: SL = 1 - 2Y**2/3; saturated: 0.
C=======================================================================
      SUBROUTINE {{ zp }}SMINS(XL, XN, GL, SL)
      IMPLICIT NONE
      DOUBLE PRECISION XL, XN, GL, SL
      DOUBLE PRECISION LNY, Y, Y2, EM, TWOE
      DOUBLE PRECISION LNYSML, LNYSAT
      PARAMETER (LNYSML = {{ ln_small | double }})
      PARAMETER (LNYSAT = {{ ln_sat | double }})
      DOUBLE PRECISION SBMF_EXPM1, SBMF_LOG1P
      EXTERNAL SBMF_EXPM1, SBMF_LOG1P
      LNY = XN*XL
      IF (LNY .LT. LNYSML) THEN
        Y = EXP(LNY)
        Y2 = Y*Y
        GL = XL + (-Y2/3.0D0 + 7.0D0*Y2*Y2/90.0D0)/XN
        SL = 1.0D0 - 2.0D0*Y2/3.0D0
        RETURN
      END IF
      IF (LNY .GT. LNYSAT) THEN
        GL = 0.0D0
        SL = 0.0D0
        RETURN
      END IF
      Y = EXP(LNY)
      EM = SBMF_EXPM1(-2.0D0*Y)
      TWOE = 2.0D0 + EM
      SL = 4.0D0*Y*(1.0D0 + EM)/(-EM*TWOE)
      IF (Y .LT. 1.0D0) THEN
        GL = XL + LOG((-EM/TWOE)/Y)/XN
        RETURN
      END IF
      GL = SBMF_LOG1P(-2.0D0*(1.0D0 + EM)/TWOE)/XN
      RETURN
      END
C
C=======================================================================
C     (ln C2, ln n2) of the tabulated reload form at X = PH/H
C     (frictionlaw's reload_table_at): monotone cubic Hermite
C     interpolant (Fritsch-Carlson slopes) over z = -ln(1 - X) through
C     the calibrated levels; the first level's values up to it; above
C     the last level ln n2 held and ln C2 rising with z at the last
C     two levels' secant slope (at least 0), at most ln 1D6 (X >= 1:
C     that cap where the slope is positive).
C=======================================================================
      SUBROUTINE {{ zp }}RTAB(X, LNC, LNN)
      IMPLICIT NONE
      DOUBLE PRECISION X, LNC, LNN
{% if reload.z | length == 1 %}
      IF (X .LT. 0.0D0) CONTINUE
C     one level: its values for every p_hist
      LNC = {{ reload.lnC2[0] | double }}
      LNN = {{ reload.lnn2[0] | double }}
      RETURN
      END
{% else %}
      DOUBLE PRECISION Z, HK, T, U, H00, H10, H01, H11, SLOPE, CMAX
      INTEGER J, NK
      PARAMETER (NK = {{ reload.z | length }})
C     above the last level: ln C2's slope in z (frictionlaw's top_slope,
C     the last two levels' secant, at least 0) and its cap
      PARAMETER (SLOPE = {{ reload.top_slope | double }})
      PARAMETER (CMAX = {{ [reload.lnC2[-1], reload.ln_c2_max] | max | double }})
      DOUBLE PRECISION ZK(NK), LCK(NK), DLCK(NK), LNK(NK), DLNK(NK)
{% for name, values in (("ZK", reload.z), ("LCK", reload.lnC2), ("DLCK", reload.dlnC2),
                        ("LNK", reload.lnn2), ("DLNK", reload.dlnn2)) %}
      PARAMETER ({{ name }} = (/
     &  {{ values | map("double") | join(",
     &  ") }} /))
{% endfor %}
      IF (.NOT. (X .LT. 1.0D0)) THEN
        LNC = LCK(NK)
        IF (SLOPE .GT. 0.0D0) LNC = CMAX
        LNN = LNK(NK)
        RETURN
      END IF
C     z = -log1p(-X) from log (Kahan: U = 1 - X rounded, then
C     log(U) X/(1 - U) is within a few ulps of log1p, which is slower)
      U = 1.0D0 - X
      IF (U .EQ. 1.0D0) THEN
        Z = X
      ELSE
        Z = -LOG(U)*(X/(1.0D0 - U))
      END IF
      IF (.NOT. (Z .GT. ZK(1))) THEN
        LNC = LCK(1)
        LNN = LNK(1)
        RETURN
      END IF
      IF (.NOT. (Z .LT. ZK(NK))) THEN
        LNC = LCK(NK)
        IF (SLOPE .GT. 0.0D0)
     &    LNC = MIN(LCK(NK) + SLOPE*(Z - ZK(NK)), CMAX)
        LNN = LNK(NK)
        RETURN
      END IF
      J = 1
   10 IF (J .LT. NK - 1 .AND. Z .GE. ZK(J + 1)) THEN
        J = J + 1
        GOTO 10
      END IF
      HK = ZK(J + 1) - ZK(J)
      T = (Z - ZK(J))/HK
      U = 1.0D0 - T
      H00 = (1.0D0 + 2.0D0*T)*U*U
      H10 = T*U*U*HK
      H01 = T*T*(3.0D0 - 2.0D0*T)
      H11 = T*T*(T - 1.0D0)*HK
      LNC = H00*LCK(J) + H10*DLCK(J) + H01*LCK(J + 1)
     &    + H11*DLCK(J + 1)
      LNN = H00*LNK(J) + H10*DLNK(J) + H01*LNK(J + 1)
     &    + H11*DLNK(J + 1)
      RETURN
      END
{% endif %}
C
C=======================================================================
C     Eq. 25 tabulated over p_hist (frictionlaw's
C     sbmf_reload_table_scalar): TAU = TMAX a1h g(x2; n2), a1h =
C     alpha1(PH) of the first loading that runs, (C2, n2) of the
C     table at PH ({{ zp }}RTAB),
C     x2h = PH C2/(H a1h), x2 = x2h (P/PH)**S2 (below P/PH = Q0 a C1
C     quadratic start, finite DTAU at P -> 0), all formed in logs:
C     ln x2h = ln(PH/H) + ln C2 - ln a1h and ln(P/PH), one log of each
C     quotient where it is a normal double (else of its terms).
{% if continuous %}
C     Continuous variant: divided by g(x2h; n2) to meet the first
C     loading at PH.
{% endif %}
C     DTAU = TAU SLP SL(x2)/P, SL = x2 g'/g ({{ zp }}SMINS), SLP =
C     d ln x2/d ln P, held below the largest double;
C     where TAU S2 SL is below 1D-290 (TAU subnormal or 0) formed in
C     logs, its log held below LNDMAX. Cap TMAX a1h for P <= PH (the
C     comparison made in logs: the cap is formed only where it
C     applies), TMAX above. G1H: cached -ln a1h (<= 0: recompute it);
C     G1OUT: the cache value for PH.
C=======================================================================
      SUBROUTINE {{ zp }}RELOAD(P, PH, G1H, TAU, DTAU, G1OUT)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT
      DOUBLE PRECISION LNA1H, X, LNC2, LNN2, XN2, LNX2H, Q, LNQ, LNX2
      DOUBLE PRECISION LG2, SL2, LNT, D, SLP, T, U
{% if continuous %}
      DOUBLE PRECISION LG2H
{% endif %}
{% if first %}
      DOUBLE PRECISION {{ zp }}LNA1
      EXTERNAL {{ zp }}LNA1
{% if continuous %}
      DOUBLE PRECISION SBMF_SMINL
      EXTERNAL SBMF_SMINL
{% endif %}
      DOUBLE PRECISION TMAX, H, S2, LNH, LNDMAX
{% else %}
      DOUBLE PRECISION SBMF_LPROD, SBMF_SMINL
      EXTERNAL SBMF_LPROD, SBMF_SMINL
      DOUBLE PRECISION TMAX, H, C1, XN1, S2, C1H, LNH, LNDMAX
{% endif %}
      PARAMETER (TMAX = {{ law.TMAX | double }})
      PARAMETER (H = {{ law.H | double }})
{% if not first %}
      PARAMETER (C1 = {{ law.C1 | double }})
      PARAMETER (XN1 = {{ law.XN1 | double }})
{% endif %}
      PARAMETER (S2 = {{ reload.s2 | double }})
{% if not first %}
      PARAMETER (C1H = C1/H)
{% endif %}
C     ln H, as the runtime's log(H) gives it
      PARAMETER (LNH = {{ ln_h | double }})
      PARAMETER (LNDMAX = {{ ln_d_max | double }})
      DOUBLE PRECISION LNQ0
C     ln Q0: below P/PH = Q0 the branch starts quadratically
      PARAMETER (LNQ0 = {{ ln_q_start | double }})
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
      X = PH/H
      CALL {{ zp }}RTAB(X, LNC2, LNN2)
      XN2 = EXP(LNN2)
      IF (1.0D-300 .LT. X .AND. X .LT. 1.0D+300) THEN
        LNX2H = LOG(X) + LNC2 - LNA1H
      ELSE
        LNX2H = LOG(PH) - LNH + LNC2 - LNA1H
      END IF
      Q = P/PH
      IF (1.0D-300 .LT. Q .AND. Q .LT. 1.0D+300) THEN
        LNQ = LOG(Q)
      ELSE
        LNQ = LOG(P) - LOG(PH)
      END IF
      SLP = S2
      IF (LNQ .LT. LNQ0) THEN
C       below P/PH = Q0: the C1 quadratic start Q0**S2 (A T + B T**2),
C       T = Q/Q0, A = 2 - S2, B = S2 - 1 (finite DTAU at P -> 0)
        T = EXP(LNQ - LNQ0)
        U = (2.0D0 - S2) + (S2 - 1.0D0)*T
        LNX2 = LNX2H + S2*LNQ0 + (LNQ - LNQ0) + LOG(U)
        SLP = 1.0D0 + (S2 - 1.0D0)*T/U
      ELSE
        LNX2 = LNX2H + S2*LNQ
      END IF
      CALL {{ zp }}SMINS(LNX2, XN2, LG2, SL2)
{% if continuous %}
C     continuous_reload: divided by g(x2h; n2), formed in logs
      LG2H = SBMF_SMINL(LNX2H, XN2)
      LNT = LNA1H + LG2 - LG2H
{% else %}
      LNT = LNA1H + LG2
{% endif %}
      TAU = TMAX*EXP(LNT)
      IF (P .GT. PH .AND. TAU .GE. TMAX) THEN
        TAU = TMAX
        DTAU = 0.0D0
        RETURN
      END IF
      D = TAU*(SLP*SL2)
      IF (D .GT. 1.0D-290) THEN
        DTAU = MIN(D/P, HUGE(DTAU))
      ELSE IF (SL2 .GT. 0.0D0) THEN
        DTAU = MIN(TMAX*SLP*SL2*EXP(MIN(LNT - LOG(P), LNDMAX)),
     &             HUGE(DTAU))
      ELSE
        DTAU = 0.0D0
      END IF
C     TAU >= TMAX a1h (exp is monotone): the cap
      IF (P .LE. PH .AND. LNT .GE. LNA1H) TAU = TMAX*EXP(LNA1H)
      RETURN
      END
C
