{#
  The two-state flattening (model limit-analysis, docs/flattening.md) of one law, included by
  core/sbmf_flat.f in place of the one-state update when the block's model is limit-analysis:
  frictionlaw._kernels_limit statement by statement ({{ zp }}TCEL: _cell; TATP: _at_pressure_d,
  which holds the shipped rate table as DATA; TRAT: limit_rates_scalar; TINT: limit_integrate;
  TRTD: limit_rates_d; TIND: limit_integrate_d; TADV: _advance; TFLT: limit_scalar; TSHR:
  limit_shear_scalar, with F5 from {{ zp }}FF5).
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
C     bilinear in A and LNS = ln s, clamped to that pressure's grid,
C     and their derivatives in A (RAA, RSA) and in LNS (RAL, RSL), 0
C     where the coordinate is clamped (the right derivative at a grid
C     line). The table (frictionlaw/data/limit_rates.csv): NR rows of
C     A, OFF the first row of each pressure less one, NS slopes; the
C     rates of row R and slope J at (R - 1) NS + J.
C=======================================================================
      SUBROUTINE {{ zp }}TATP(IP, A, LNS, RA, RS, RAA, RSA, RAL, RSL)
      IMPLICIT NONE
      INTEGER IP, R, J, I, R0, R1
      DOUBLE PRECISION A, LNS, RA, RS, RAA, RSA, RAL, RSL
      DOUBLE PRECISION UA, US, TA, TS, GA, GS, A0, A1, S0, S1
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
      UA = (A - AR(R))/(AR(R + 1) - AR(R))
      US = (LNS - LS(J))/(LS(J + 1) - LS(J))
      TA = MIN(MAX(UA, 0.0D0), 1.0D0)
      TS = MIN(MAX(US, 0.0D0), 1.0D0)
      GA = 0.0D0
      IF (0.0D0 .LE. UA .AND. UA .LT. 1.0D0)
     &  GA = 1.0D0/(AR(R + 1) - AR(R))
      GS = 0.0D0
      IF (0.0D0 .LE. US .AND. US .LT. 1.0D0)
     &  GS = 1.0D0/(LS(J + 1) - LS(J))
      R0 = (R - 1)*NS + J
      R1 = R*NS + J
      A0 = (1 - TS)*DA(R0) + TS*DA(R0 + 1)
      A1 = (1 - TS)*DA(R1) + TS*DA(R1 + 1)
      S0 = (1 - TS)*DS(R0) + TS*DS(R0 + 1)
      S1 = (1 - TS)*DS(R1) + TS*DS(R1 + 1)
      RA = (1 - TA)*A0 + TA*A1
      RS = (1 - TA)*S0 + TA*S1
      RAA = GA*(A1 - A0)
      RSA = GA*(S1 - S0)
      RAL = GS*((1 - TA)*(DA(R0 + 1) - DA(R0))
     &      + TA*(DA(R1 + 1) - DA(R1)))
      RSL = GS*((1 - TA)*(DS(R0 + 1) - DS(R0))
     &      + TA*(DS(R1 + 1) - DS(R1)))
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
      DOUBLE PRECISION D1, D2, D3, D4
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
      CALL {{ zp }}TATP(I, A, LNS, A0, S0, D1, D2, D3, D4)
      CALL {{ zp }}TATP(I + 1, A, LNS, A1, S1, D1, D2, D3, D4)
      RA = MAX((1 - W)*A0 + W*A1, 0.0D0)
      RS = (1 - W)*S0 + W*S1
      RETURN
      END
C
C=======================================================================
C     {{ zp }}TRAT (RA, RS, the same operations) and their derivatives in
C     X (RAX, RSX), A (RAA, RSA) and S (RAS, RSS); those of RA 0 where
C     it is held at 0.
C=======================================================================
      SUBROUTINE {{ zp }}TRTD(X, A, S, RA, RS, RAX, RSX, RAA, RSA, RAS,
     &                        RSS)
      IMPLICIT NONE
      DOUBLE PRECISION X, A, S, RA, RS, RAX, RSX, RAA, RSA, RAS, RSS
      DOUBLE PRECISION LG, UW, W, GW, LNS, RAW
      DOUBLE PRECISION A0, S0, A0A, S0A, A0L, S0L
      DOUBLE PRECISION A1, S1, A1A, S1A, A1L, S1L
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
      LG = LOG(PT(I + 1)/PT(I))
      UW = LOG(X/PT(I))/LG
      W = MIN(MAX(UW, 0.0D0), 1.0D0)
      GW = 0.0D0
      IF (0.0D0 .LE. UW .AND. UW .LT. 1.0D0) GW = 1.0D0/(X*LG)
      LNS = LOG(S)
      CALL {{ zp }}TATP(I, A, LNS, A0, S0, A0A, S0A, A0L, S0L)
      CALL {{ zp }}TATP(I + 1, A, LNS, A1, S1, A1A, S1A, A1L, S1L)
      RAW = (1 - W)*A0 + W*A1
      RS = (1 - W)*S0 + W*S1
      RSX = GW*(S1 - S0)
      RSA = (1 - W)*S0A + W*S1A
      RSS = ((1 - W)*S0L + W*S1L)/S
      IF (.NOT. (RAW .GT. 0.0D0)) THEN
        RA = 0.0D0
        RAX = 0.0D0
        RAA = 0.0D0
        RAS = 0.0D0
        RETURN
      END IF
      RA = RAW
      RAX = GW*(A1 - A0)
      RAA = (1 - W)*A0A + W*A1A
      RAS = ((1 - W)*A0L + W*A1L)/S
      RETURN
      END
C
{% if flat.edge %}
C=======================================================================
C     The block's edge slope G = E(A) and GA = dE/dA: linear between
C     its NE values at the equally spaced contact fractions 0 .. 1 (the
C     right derivative at a grid point, 0 at A = 1).
C=======================================================================
      SUBROUTINE {{ zp }}TEDG(A, G, GA)
      IMPLICIT NONE
      INTEGER NE, I
      PARAMETER (NE = {{ flat.edge | length }})
      DOUBLE PRECISION A, G, GA, U, EDG(NE)
{% for statement in flat.edge_data %}
{{ statement }}
{% endfor %}
      U = A*DBLE(NE - 1)
      I = MIN(INT(U), NE - 2)
      G = EDG(I + 1) + (U - DBLE(I))*(EDG(I + 2) - EDG(I + 1))
      GA = 0.0D0
      IF (U .LT. DBLE(NE - 1)) THEN
        GA = (EDG(I + 2) - EDG(I + 1))*DBLE(NE - 1)
      END IF
      RETURN
      END
C
{% endif %}
C=======================================================================
C     (A, S) after the stretch STR at X = p/H_P: the explicit midpoint
C     rule in (A, ln s), steps of STEP (the last shorter), A at most 1
C     (it then stops), S at least SFLR.
C=======================================================================
      SUBROUTINE {{ zp }}TINT(A, S, X, STR)
      IMPLICIT NONE
      DOUBLE PRECISION A, S, X, STR, Q, LEFT, H, SQ, RA, RS, AM, QM, SM
      DOUBLE PRECISION STEP, SFLR
{% if flat.edge %}
      DOUBLE PRECISION G, GA
{% endif %}
      PARAMETER (STEP = {{ flat.limit.step | double }})
      PARAMETER (SFLR = {{ flat.limit.s_floor | double }})
      A = MIN(A, 1.0D0)
{% if flat.edge %}
      Q = LOG(MAX(S, 1.0D-300))
{% else %}
      Q = LOG(MAX(S, SFLR))
{% endif %}
      LEFT = STR
      DO WHILE (LEFT .GT. 1.0D-12 .AND. A .LT. 1.0D0)
        H = MIN(STEP, LEFT)
{% if flat.edge %}
        CALL {{ zp }}TEDG(A, G, GA)
        SQ = MAX(EXP(Q)*G, SFLR)
{% else %}
        SQ = MAX(EXP(Q), SFLR)
{% endif %}
        CALL {{ zp }}TRAT(X, A, SQ, RA, RS)
        AM = MIN(A + 0.5D0*H*RA, 1.0D0)
        QM = Q + 0.5D0*H*RS/SQ
{% if flat.edge %}
        CALL {{ zp }}TEDG(AM, G, GA)
        SM = MAX(EXP(QM)*G, SFLR)
{% else %}
        SM = MAX(EXP(QM), SFLR)
{% endif %}
        CALL {{ zp }}TRAT(X, AM, SM, RA, RS)
        A = MIN(A + H*RA, 1.0D0)
        Q = Q + H*RS/SM
        LEFT = LEFT - H
      END DO
{% if flat.edge %}
      CALL {{ zp }}TEDG(A, G, GA)
      S = MAX(EXP(Q)*G, SFLR)
{% else %}
      S = MAX(EXP(Q), SFLR)
{% endif %}
      RETURN
      END
C
C=======================================================================
C     {{ zp }}TINT (A, S the same operations) with d A/dP of its end
C     carried through the same steps: AP in, the start's d A/dP; out,
C     the end's; XP = dX/dP (the start's slope does not depend on P);
C     0 through a step where A reaches 1 or S its floor.
C=======================================================================
      SUBROUTINE {{ zp }}TIND(A, S, X, STR, AP, XP)
      IMPLICIT NONE
      DOUBLE PRECISION A, S, X, STR, AP, XP, Q, QD, LEFT, H, E, SQ, SQD
      DOUBLE PRECISION RA, RS, RAX, RSX, RAA, RSA, RAS, RSS, RAD, RSD
      DOUBLE PRECISION AMR, AM, AMD, QM, QMD, EM, SM, SMD, AR
      DOUBLE PRECISION STEP, SFLR
{% if flat.edge %}
      DOUBLE PRECISION G, GA
{% endif %}
      PARAMETER (STEP = {{ flat.limit.step | double }})
      PARAMETER (SFLR = {{ flat.limit.s_floor | double }})
      A = MIN(A, 1.0D0)
      IF (.NOT. (A .LT. 1.0D0)) AP = 0.0D0
{% if flat.edge %}
      Q = LOG(MAX(S, 1.0D-300))
{% else %}
      Q = LOG(MAX(S, SFLR))
{% endif %}
      QD = 0.0D0
      LEFT = STR
      DO WHILE (LEFT .GT. 1.0D-12 .AND. A .LT. 1.0D0)
        H = MIN(STEP, LEFT)
{% if flat.edge %}
        CALL {{ zp }}TEDG(A, G, GA)
        E = EXP(Q)*G
        SQ = MAX(E, SFLR)
        SQD = 0.0D0
        IF (E .GT. SFLR) SQD = E*QD + EXP(Q)*GA*AP
{% else %}
        E = EXP(Q)
        SQ = MAX(E, SFLR)
        SQD = 0.0D0
        IF (E .GT. SFLR) SQD = E*QD
{% endif %}
        CALL {{ zp }}TRTD(X, A, SQ, RA, RS, RAX, RSX, RAA, RSA, RAS, RSS)
        RAD = RAX*XP + RAA*AP + RAS*SQD
        RSD = RSX*XP + RSA*AP + RSS*SQD
        AMR = A + 0.5D0*H*RA
        AM = MIN(AMR, 1.0D0)
        AMD = 0.0D0
        IF (AMR .LT. 1.0D0) AMD = AP + 0.5D0*H*RAD
        QM = Q + 0.5D0*H*RS/SQ
        QMD = QD + 0.5D0*H*(RSD - RS*SQD/SQ)/SQ
{% if flat.edge %}
        CALL {{ zp }}TEDG(AM, G, GA)
        EM = EXP(QM)*G
        SM = MAX(EM, SFLR)
        SMD = 0.0D0
        IF (EM .GT. SFLR) SMD = EM*QMD + EXP(QM)*GA*AMD
{% else %}
        EM = EXP(QM)
        SM = MAX(EM, SFLR)
        SMD = 0.0D0
        IF (EM .GT. SFLR) SMD = EM*QMD
{% endif %}
        CALL {{ zp }}TRTD(X, AM, SM, RA, RS, RAX, RSX, RAA, RSA, RAS, RSS)
        RAD = RAX*XP + RAA*AMD + RAS*SMD
        RSD = RSX*XP + RSA*AMD + RSS*SMD
        AR = A + H*RA
        A = MIN(AR, 1.0D0)
        IF (AR .LT. 1.0D0) THEN
          AP = AP + H*RAD
        ELSE
          AP = 0.0D0
        END IF
        Q = Q + H*RS/SM
        QD = QD + H*(RSD - RS*SMD/SM)/SM
        LEFT = LEFT - H
      END DO
{% if flat.edge %}
      CALL {{ zp }}TEDG(A, G, GA)
      S = MAX(EXP(Q)*G, SFLR)
{% else %}
      S = MAX(EXP(Q), SFLR)
{% endif %}
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
C     the update's d alpha/dP where Eq. F5 reads it (P >= PH and ANEW
C     above alpha1(P); else 0), carried through the integration
C     ({{ zp }}TIND). DEPS <= 0, P <= 1D-12 H and full contact leave both
C     states as they are.
C=======================================================================
      SUBROUTINE {{ zp }}TFLT(P, PH, AF, SF, DEPS, SIGY, ANEW, SNEW,
     &                        DADP)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, AF, SF, DEPS, SIGY, ANEW, SNEW, DADP
      DOUBLE PRECISION S0, XK, A1, D1, X, AP
      DOUBLE PRECISION SLOPE, S0F, SIGYF, PMIN, BETA, STR, PRF
      PARAMETER (SLOPE = {{ flat.slope | double }})
      PARAMETER (S0F = {{ flat.s0 | double }})
      PARAMETER (SIGYF = {{ flat.sigma_y | double }})
      PARAMETER (PMIN = {{ flat.p_min | double }})
      PARAMETER (BETA = {{ flat.beta | double }})
      PARAMETER (STR = {{ flat.stretch | double }})
      PARAMETER (PRF = {{ flat.limit.prandtl | double }})
      ANEW = AF
      SNEW = SF
      DADP = 0.0D0
      IF (.NOT. (DEPS .GT. 0.0D0 .AND. P .GT. PMIN .AND.
     &    AF .LT. 1.0D0)) RETURN
{% if flat.edge %}
C     the flank's turn r = SF/E(AF) (1: never flattened)
      S0 = 1.0D0
      IF (SF .GT. 0.0D0) THEN
        CALL {{ zp }}TEDG(AF, A1, D1)
        S0 = SF/A1
      END IF
{% else %}
      S0 = SLOPE
      IF (SF .GT. 0.0D0) S0 = SF
{% endif %}
      XK = 0.5D0*S0F
      IF (SIGY .GT. 0.0D0) XK = XK*(SIGY/SIGYF)
      IF (P .LT. PH) THEN
        CALL {{ zp }}TADV(P, PH, AF, S0, DEPS, XK, ANEW, SNEW)
        RETURN
      END IF
C     first loading: d A/dP carried forward from alpha1' where the start
C     is alpha1(P), and from X = P/H_P
      CALL {{ zp }}A1D(P, A1, D1)
      ANEW = MAX(AF, A1)
      AP = 0.0D0
      IF (A1 .GE. AF) AP = D1
      SNEW = S0
      X = P/(PRF*XK)
      CALL {{ zp }}TIND(ANEW, SNEW, X, STR*BETA*DEPS, AP, 1.0D0/(PRF*XK))
      IF (.NOT. (ANEW .GT. AF)) THEN
        ANEW = AF
        AP = 0.0D0
      END IF
      IF (ANEW .GT. A1) DADP = AP
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
