{#
  The two-state flattening (model limit-analysis, docs/flattening.md) of one law, included by
  core/sbmf_flat.f in place of the one-state update when the block's model is limit-analysis:
  frictionlaw._kernels_limit statement by statement ({{ zp }}TCEL: _cell; TATP: _at_pressure,
  which holds the shipped rate table as DATA; TRAT: limit_rates_scalar; TINT: limit_integrate;
  TADV: _advance; TFLT: limit_scalar; TSHR: limit_shear_scalar, with F5 from {{ zp }}FF5).
  Context: the law's CoreLaw (zp, law) and flat, its FlatSpec, flat.limit its LimitSpec
  (frictionlaw.export._flat; the table's values as the package's CSV gives them).
#}
C=======================================================================
C     The interval [V(I), V(I+1)] of V(LO..HI) (ascending) holding X,
C     clamped to LO..HI-1.
C=======================================================================
      INTEGER FUNCTION {{ zp }}TCEL(V, LO, HI, X)
      IMPLICIT NONE
      INTEGER LO, HI, I
      DOUBLE PRECISION V(*), X
      I = LO
      DO WHILE (I .LT. HI - 1)
        IF (.NOT. (X .GT. V(I + 1))) EXIT
        I = I + 1
      END DO
      {{ zp }}TCEL = I
      RETURN
      END
C
C=======================================================================
C     The rates (RA, RS) = (dA/d eps, ds/d eps) of the rigid-perfectly
C     plastic optimum of the wedge cell at the tabulated pressure IP,
C     bilinear in A and LNS = ln s, clamped to that pressure's grid.
C     The table (frictionlaw/data/limit_rates.csv): NR rows of A, OFF
C     the first row of each pressure less one, NS slopes; the rates of
C     row R and slope J at (R - 1) NS + J.
C=======================================================================
      SUBROUTINE {{ zp }}TATP(IP, A, LNS, RA, RS)
      IMPLICIT NONE
      INTEGER IP, R, J, I, R0, R1
      DOUBLE PRECISION A, LNS, RA, RS, TA, TS
      INTEGER {{ zp }}TCEL
      EXTERNAL {{ zp }}TCEL
      INTEGER NP, NR, NS
      PARAMETER (NP = {{ flat.limit.pressures | length }})
      PARAMETER (NR = {{ flat.limit.a | length }})
      PARAMETER (NS = {{ flat.limit.ln_s | length }})
      INTEGER OFF(NP + 1)
      DOUBLE PRECISION AR(NR), LS(NS), DA(NR*NS), DS(NR*NS)
{% for statement in flat.limit.data %}
{{ statement }}
{% endfor %}
      R = {{ zp }}TCEL(AR, OFF(IP) + 1, OFF(IP + 1), A)
      J = {{ zp }}TCEL(LS, 1, NS, LNS)
      TA = MIN(MAX((A - AR(R))/(AR(R + 1) - AR(R)), 0.0D0), 1.0D0)
      TS = MIN(MAX((LNS - LS(J))/(LS(J + 1) - LS(J)), 0.0D0), 1.0D0)
      R0 = (R - 1)*NS + J
      R1 = R*NS + J
      RA = (1 - TA)*((1 - TS)*DA(R0) + TS*DA(R0 + 1))
     &     + TA*((1 - TS)*DA(R1) + TS*DA(R1 + 1))
      RS = (1 - TA)*((1 - TS)*DS(R0) + TS*DS(R0 + 1))
     &     + TA*((1 - TS)*DS(R1) + TS*DS(R1 + 1))
      RETURN
      END
C
C=======================================================================
C     (RA, RS) at X = p/H_P, A and S: linear in ln X between the two
C     tabulated pressures around it (clamped), each at the same A;
C     RA >= 0 (a node's flattening never falls).
C=======================================================================
      SUBROUTINE {{ zp }}TRAT(X, A, S, RA, RS)
      IMPLICIT NONE
      DOUBLE PRECISION X, A, S, RA, RS, W, LNS, A0, S0, A1, S1
      INTEGER I
      INTEGER {{ zp }}TCEL
      EXTERNAL {{ zp }}TCEL
      INTEGER NP
      PARAMETER (NP = {{ flat.limit.pressures | length }})
      DOUBLE PRECISION PT(NP)
      PARAMETER (PT = (/
     &  {{ flat.limit.pressures | map("double") | join(",
     &  ") }} /))
      I = {{ zp }}TCEL(PT, 1, NP, X)
      W = MIN(MAX(LOG(X/PT(I))/LOG(PT(I + 1)/PT(I)), 0.0D0), 1.0D0)
      LNS = LOG(S)
      CALL {{ zp }}TATP(I, A, LNS, A0, S0)
      CALL {{ zp }}TATP(I + 1, A, LNS, A1, S1)
      RA = MAX((1 - W)*A0 + W*A1, 0.0D0)
      RS = (1 - W)*S0 + W*S1
      RETURN
      END
C
C=======================================================================
C     (A, S) after the stretch STR at X = p/H_P: the explicit midpoint
C     rule in (A, ln s), steps of STEP (the last shorter), A at most 1
C     (it then stops), S at least SFLR.
C=======================================================================
      SUBROUTINE {{ zp }}TINT(A, S, X, STR)
      IMPLICIT NONE
      DOUBLE PRECISION A, S, X, STR, Q, LEFT, H, SQ, RA, RS, AM, QM, SM
      DOUBLE PRECISION STEP, SFLR
      PARAMETER (STEP = {{ flat.limit.step | double }})
      PARAMETER (SFLR = {{ flat.limit.s_floor | double }})
      A = MIN(A, 1.0D0)
      Q = LOG(MAX(S, SFLR))
      LEFT = STR
      DO WHILE (LEFT .GT. 1.0D-12 .AND. A .LT. 1.0D0)
        H = MIN(STEP, LEFT)
        SQ = MAX(EXP(Q), SFLR)
        CALL {{ zp }}TRAT(X, A, SQ, RA, RS)
        AM = MIN(A + 0.5D0*H*RA, 1.0D0)
        QM = Q + 0.5D0*H*RS/SQ
        SM = MAX(EXP(QM), SFLR)
        CALL {{ zp }}TRAT(X, AM, SM, RA, RS)
        A = MIN(A + H*RA, 1.0D0)
        Q = Q + H*RS/SM
        LEFT = LEFT - H
      END DO
      S = MAX(EXP(Q), SFLR)
      RETURN
      END
C
C=======================================================================
C     One node's states at the pressure P (XK the shear flow stress):
C     from A0 = max(AF, alpha1(max(P, PH))) and the slope S0 over the
C     stretch STR BETA DEPS; ANEW never below AF.
C=======================================================================
      SUBROUTINE {{ zp }}TADV(P, PH, AF, S0, DEPS, XK, ANEW, SNEW)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, AF, S0, DEPS, XK, ANEW, SNEW, A1, D1
      DOUBLE PRECISION BETA, STR, PRF
      PARAMETER (BETA = {{ flat.beta | double }})
      PARAMETER (STR = {{ flat.stretch | double }})
      PARAMETER (PRF = {{ flat.limit.prandtl | double }})
      CALL {{ zp }}A1D(MAX(P, PH), A1, D1)
      ANEW = MAX(AF, A1)
      SNEW = S0
      CALL {{ zp }}TINT(ANEW, SNEW, P/(PRF*XK), STR*BETA*DEPS)
      ANEW = MAX(ANEW, AF)
      RETURN
      END
C
C=======================================================================
C     One node's two states over a strain increment: from the
C     committed AF and SF (0: the block's slope) and the trial history
C     PH, at P with the bulk's equivalent plastic strain increment
C     DEPS (flow stress SIGY, <= 0: the file's sigma_y): ANEW, SNEW and
C     the update's d alpha/dP (a forward difference of relative step
C     DP, where Eq. F5 reads it: P >= PH and ANEW above alpha1(P);
C     else 0). DEPS <= 0, P <= 1D-12 H and full contact leave both
C     states as they are.
C=======================================================================
      SUBROUTINE {{ zp }}TFLT(P, PH, AF, SF, DEPS, SIGY, ANEW, SNEW,
     &                        DADP)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, AF, SF, DEPS, SIGY, ANEW, SNEW, DADP
      DOUBLE PRECISION S0, XK, A1, D1, PD, AD, SD
      DOUBLE PRECISION SLOPE, S0F, SIGYF, PMIN, DP
      PARAMETER (SLOPE = {{ flat.slope | double }})
      PARAMETER (S0F = {{ flat.s0 | double }})
      PARAMETER (SIGYF = {{ flat.sigma_y | double }})
      PARAMETER (PMIN = {{ flat.p_min | double }})
      PARAMETER (DP = {{ flat.limit.dp | double }})
      ANEW = AF
      SNEW = SF
      DADP = 0.0D0
      IF (.NOT. (DEPS .GT. 0.0D0 .AND. P .GT. PMIN .AND.
     &    AF .LT. 1.0D0)) RETURN
      S0 = SLOPE
      IF (SF .GT. 0.0D0) S0 = SF
      XK = 0.5D0*S0F
      IF (SIGY .GT. 0.0D0) XK = XK*(SIGY/SIGYF)
      CALL {{ zp }}TADV(P, PH, AF, S0, DEPS, XK, ANEW, SNEW)
      IF (P .LT. PH) RETURN
      CALL {{ zp }}A1D(P, A1, D1)
      IF (.NOT. (ANEW .GT. A1)) RETURN
      PD = P*(1.0D0 + DP)
      CALL {{ zp }}TADV(PD, PH, AF, S0, DEPS, XK, AD, SD)
      DADP = (AD - ANEW)/(PD - P)
      RETURN
      END
C
C=======================================================================
C     The shear limit with the two-state flattening: without strain on
C     a surface never flattened (DEPS <= 0, AF = 0), and for P <= 0,
C     {{ zp }}SHEAR itself and both states as passed. Otherwise the
C     trial states ANEW, SNEW of {{ zp }}TFLT, then F5 ({{ zp }}FF5).
C=======================================================================
      SUBROUTINE {{ zp }}TSHR(P, PH, AF, SF, DEPS, SIGY, G1H, TAU,
     &                        DTAU, G1OUT, ANEW, SNEW)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, AF, SF, DEPS, SIGY, G1H, TAU, DTAU
      DOUBLE PRECISION G1OUT, ANEW, SNEW, DADP
      ANEW = AF
      SNEW = SF
      IF (.NOT. (P .GT. 0.0D0) .OR.
     &    (.NOT. (DEPS .GT. 0.0D0) .AND. AF .EQ. 0.0D0)) THEN
        CALL {{ zp }}SHEAR(P, PH, G1H, TAU, DTAU, G1OUT)
        RETURN
      END IF
      CALL {{ zp }}TFLT(P, PH, AF, SF, DEPS, SIGY, ANEW, SNEW, DADP)
      CALL {{ zp }}FF5(P, PH, ANEW, 0.0D0, DADP, G1H, TAU, DTAU, G1OUT)
      RETURN
      END
C
