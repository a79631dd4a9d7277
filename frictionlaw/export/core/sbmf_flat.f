{#
  The flattening of the asperities under bulk strain of one law (issue 43, docs/flattening.md,
  Eqs. F5-F6), included by core/sbmf_law.f after the law's routines when its parameter file has
  a flattening block: frictionlaw._kernels_flattening statement by statement ({{ zp }}A1D:
  alpha1 and its slope; FINV: alpha1_inverse; FPAN: flat_panels; FSWTC: flat_switch; FQUAD:
  flat_quad; FKINK: flat_kinked; FSOLV:
  flattening_solve; FRATE: flat_rate; FLAT: flattening_scalar; FF5: flat_shear_of; FSHR:
  flat_shear_scalar). For the two-state model (flat.limit set) the one-state update (FRATE to
  FLAT, FSHR) gives way to core/sbmf_limit.f, which shares A1D, FINV and FF5. Context: the
  law's CoreLaw (zp, law, first) and flat, its FlatSpec (frictionlaw.export._flat, host units).
#}
C=======================================================================
C     alpha1(T) and d alpha1/dT of the first loading that runs: its
C     shear TAU and DTAU ({{ zp }}FIRST) over TMAX.
C=======================================================================
      SUBROUTINE {{ zp }}A1D(T, A, D)
      IMPLICIT NONE
      DOUBLE PRECISION T, A, D, TAU, DTAU, G1
      DOUBLE PRECISION TMAX
      PARAMETER (TMAX = {{ law.TMAX | double }})
      CALL {{ zp }}FIRST(T, TAU, DTAU, G1)
      A = TAU/TMAX
      D = DTAU/TMAX
      RETURN
      END
C
C=======================================================================
C     The pressure in [XLO, XHI] whose alpha1 is A (alpha1(XLO) < A;
C     XHI where alpha1(XHI) <= A): Newton in ln P on ln alpha1,
C     bisection in ln P where a step leaves the bracket and every
C     eighth step; to 1D-15 in ln P.
C=======================================================================
      DOUBLE PRECISION FUNCTION {{ zp }}FINV(A, XLO, XHI)
      IMPLICIT NONE
      DOUBLE PRECISION A, XLO, XHI
      DOUBLE PRECISION LNA, YLO, YHI, Y, YN, P, AL, D, G, S
      INTEGER IT
      LOGICAL BIS
      CALL {{ zp }}A1D(XHI, AL, D)
      IF (.NOT. (A .LT. AL)) THEN
        {{ zp }}FINV = XHI
        RETURN
      END IF
      LNA = LOG(A)
      YLO = LOG(XLO)
      YHI = LOG(XHI)
      Y = YLO
      DO IT = 0, 199
        P = EXP(Y)
        CALL {{ zp }}A1D(P, AL, D)
        IF (.NOT. (AL .GT. 0.0D0)) THEN
          G = -HUGE(1.0D0)
        ELSE
          G = LOG(AL) - LNA
        END IF
        IF (G .EQ. 0.0D0) THEN
          {{ zp }}FINV = P
          RETURN
        END IF
        IF (G .LT. 0.0D0) THEN
          YLO = Y
        ELSE
          YHI = Y
        END IF
        S = 0.0D0
        IF (AL .GT. 0.0D0) S = P*D/AL
        BIS = .TRUE.
        IF (S .GT. 0.0D0) THEN
          YN = Y - G/S
          IF (ABS(YN - Y) .LE. 1.0D-15*(1.0D0 + ABS(Y))) THEN
            {{ zp }}FINV = EXP(YN)
            RETURN
          END IF
          BIS = .NOT. (YLO .LT. YN .AND. YN .LT. YHI)
          IF (MOD(IT, 8) .EQ. 7) BIS = .TRUE.
        END IF
        IF (BIS) YN = 0.5D0*(YLO + YHI)
        IF (ABS(YN - Y) .LE. 1.0D-15*(1.0D0 + ABS(Y)) .OR.
     &      YHI - YLO .LE. 1.0D-15*(1.0D0 + ABS(YHI))) THEN
          {{ zp }}FINV = EXP(YN)
          RETURN
        END IF
        Y = YN
      END DO
      {{ zp }}FINV = EXP(Y)
      RETURN
      END
C
{% if not flat.limit %}
C=======================================================================
C     The lattice's rate at the fraction A and the weight of its term
C     in the tangent (Eq. F2c): CL = 1 + SL (1 - A), XL = 1, or where
C     that exceeds the hardening's limit CMX (1 - A) (CMX = 6 P / h;
C     HUGE or above: none), CL = CMX (1 - A), XL = 0.
C=======================================================================
      SUBROUTINE {{ zp }}FRATE(SL, A, CMX, CL, XL)
      IMPLICIT NONE
      DOUBLE PRECISION SL, A, CMX, CL, XL
      CL = 1.0D0 + SL*(1.0D0 - A)
      XL = 1.0D0
      IF (CMX .LT. HUGE(1.0D0)) THEN
        IF (CL .GT. CMX*(1.0D0 - A)) THEN
          CL = CMX*(1.0D0 - A)
          XL = 0.0D0
        END IF
      END IF
      RETURN
      END
C
C=======================================================================
C     S1 = int alpha1'(P cosh v) cosh v sinh(v)**2 / W dv and S2 =
C     int alpha1'(P cosh v) cosh v (1 - G CL cosh v sinh(v)**3) / W**2
C     dv over UA..UB, W = 1 + G cosh v sinh v CL, CL = 1 + SL (1 -
C     alpha1) the lattice's rate, G = P/s0, SL = tan(theta), where the
C     integrand is smooth; where CL exceeds the hardening's limit CMX
C     (1 - alpha1) (Eq. F2c, CMX = 6 P / h: P times a function of t)
C     CL is that and the second integrand is alpha1' cosh v / W**2
C     (FRATE). Gauss-Legendre
C     on equal panels no wider than WIDTH, 8 nodes a panel, 4 on an
C     interval narrower than NARR2 and 2 below NARR1.
C=======================================================================
      SUBROUTINE {{ zp }}FPAN(P, UA, UB, G, SL, CMX, S1, S2)
      IMPLICIT NONE
      DOUBLE PRECISION P, UA, UB, G, SL, CMX, S1, S2
      DOUBLE PRECISION SPAN, HP, XMID, V, CH, SH, A, D, CL, XL, W
      INTEGER N, K, J, K0, M
      DOUBLE PRECISION GX({{ flat.gx | length }}), GW({{ flat.gw | length }})
      DOUBLE PRECISION WIDTH, NARR1, NARR2
      PARAMETER (GX = (/
     &  {{ flat.gx | map("double") | join(",
     &  ") }} /))
      PARAMETER (GW = (/
     &  {{ flat.gw | map("double") | join(",
     &  ") }} /))
      PARAMETER (WIDTH = {{ flat.width | double }})
      PARAMETER (NARR1 = {{ flat.narrow[0] | double }})
      PARAMETER (NARR2 = {{ flat.narrow[1] | double }})
      SPAN = UB - UA
      N = MAX(1, CEILING(ABS(SPAN)/WIDTH))
      HP = SPAN/DBLE(N)
      IF (ABS(HP) .LE. NARR1) THEN
        K0 = 0
        M = 2
      ELSE IF (ABS(HP) .LE. NARR2) THEN
        K0 = 2
        M = 4
      ELSE
        K0 = 6
        M = 8
      END IF
      S1 = 0.0D0
      S2 = 0.0D0
      DO K = 0, N - 1
        XMID = UA + (DBLE(K) + 0.5D0)*HP
        DO J = K0 + 1, K0 + M
          V = XMID + 0.5D0*HP*GX(J)
          CH = COSH(V)
          SH = SINH(V)
          CALL {{ zp }}A1D(P*CH, A, D)
          CALL {{ zp }}FRATE(SL, A, CMX, CL, XL)
          W = 1.0D0 + G*CH*SH*CL
          S1 = S1 + GW(J)*(D*CH*SH*SH/W)
          S2 = S2 + GW(J)*(D*CH*(1.0D0 - XL*G*CL*CH*SH*SH*SH)/(W*W))
        END DO
      END DO
      S1 = 0.5D0*HP*S1
      S2 = 0.5D0*HP*S2
      RETURN
      END
C
C=======================================================================
C     VC: v where Eq. F2c's limit starts to act on the way up from P0
C     (t = P cosh v): CMX (1 - A) falls below 1 + SL (1 - A) above
C     A_c = 1 - 1/(CMX - SL), everywhere for CMX <= SL + 1. There the
C     strain integral's integrand has a kink and the tangent's a jump,
C     which the panels must not straddle. HUGE where the limit acts
C     nowhere, from P0 on or only beyond CAP.
C=======================================================================
      DOUBLE PRECISION FUNCTION {{ zp }}FSWTC(P, P0, CAP, SL, CMX)
      IMPLICIT NONE
      DOUBLE PRECISION P, P0, CAP, SL, CMX, AC, A0, D0, TC
      DOUBLE PRECISION {{ zp }}FINV
      EXTERNAL {{ zp }}FINV
      {{ zp }}FSWTC = HUGE(1.0D0)
      IF (.NOT. (CMX .LT. HUGE(1.0D0) .AND. CMX .GT. SL + 1.0D0))
     &  RETURN
      AC = 1.0D0 - 1.0D0/(CMX - SL)
      CALL {{ zp }}A1D(P0, A0, D0)
      IF (.NOT. (AC .GT. A0)) RETURN
      TC = {{ zp }}FINV(AC, P0, CAP)
      IF (.NOT. (TC .LT. CAP)) RETURN
      {{ zp }}FSWTC = ACOSH(TC/P)
      RETURN
      END
C
C=======================================================================
C     {{ zp }}FPAN's two integrals over UA..UB (UB < UA: their
C     negatives), split at VC, where Eq. F2c's limit starts to act
C     ({{ zp }}FSWTC; HUGE: nowhere), each piece by {{ zp }}FKINK.
C=======================================================================
      SUBROUTINE {{ zp }}FQUAD(P, UA, UB, G, SL, CMX, VC, S1, S2)
      IMPLICIT NONE
      DOUBLE PRECISION P, UA, UB, G, SL, CMX, VC, S1, S2
      DOUBLE PRECISION SGN, XLO, XHI, R1, R2
      SGN = 1.0D0
      XLO = UA
      XHI = UB
      IF (XHI .LT. XLO) THEN
        SGN = -1.0D0
        XLO = UB
        XHI = UA
      END IF
      IF (XLO .LT. VC .AND. VC .LT. XHI) THEN
        CALL {{ zp }}FKINK(P, XLO, VC, G, SL, CMX, S1, S2)
        CALL {{ zp }}FKINK(P, VC, XHI, G, SL, CMX, R1, R2)
        S1 = S1 + R1
        S2 = S2 + R2
      ELSE
        CALL {{ zp }}FKINK(P, XLO, XHI, G, SL, CMX, S1, S2)
      END IF
      S1 = SGN*S1
      S2 = SGN*S2
      RETURN
      END
C
C=======================================================================
C     {{ zp }}FPAN's two integrals over XLO..XHI (XLO <= XHI){% if first %},
C     split where the tabulated first loading's slope has kinks: at its
C     levels and where its top level's power law reaches ln alpha = 0
C     (v = acosh(p_j/P)){% endif %}.
C=======================================================================
      SUBROUTINE {{ zp }}FKINK(P, XLO, XHI, G, SL, CMX, S1, S2)
      IMPLICIT NONE
      DOUBLE PRECISION P, XLO, XHI, G, SL, CMX, S1, S2
{% if first %}
      DOUBLE PRECISION T1, T2, R1, R2, A, TK, VK
      INTEGER J, NJ
      DOUBLE PRECISION H
      PARAMETER (H = {{ law.H | double }})
      PARAMETER (NJ = {{ first.u | length }})
      DOUBLE PRECISION UK(NJ), VKN(NJ), DK(NJ)
{% for name, values in (("UK", first.u), ("VKN", first.v), ("DK", first.d)) %}
      PARAMETER ({{ name }} = (/
     &  {{ values | map("double") | join(",
     &  ") }} /))
{% endfor %}
{% endif %}
{% if first %}
      T1 = 0.0D0
      T2 = 0.0D0
      A = XLO
      DO J = 1, NJ + 1
        IF (J .LE. NJ) THEN
          TK = H*EXP(UK(J))
        ELSE
          IF (.NOT. (DK(NJ) .GT. 0.0D0)) EXIT
          TK = H*EXP(UK(NJ) - VKN(NJ)/DK(NJ))
        END IF
        IF (.NOT. (TK .GT. P)) CYCLE
        VK = ACOSH(TK/P)
        IF (VK .GE. XHI) EXIT
        IF (VK .GT. A) THEN
          CALL {{ zp }}FPAN(P, A, VK, G, SL, CMX, R1, R2)
          T1 = T1 + R1
          T2 = T2 + R2
          A = VK
        END IF
      END DO
      CALL {{ zp }}FPAN(P, A, XHI, G, SL, CMX, R1, R2)
      S1 = T1 + R1
      S2 = T2 + R2
{% else %}
      CALL {{ zp }}FPAN(P, XLO, XHI, G, SL, CMX, S1, S2)
{% endif %}
      RETURN
      END
C
C=======================================================================
C     Eq. F6 from P0 at the pressure P: the flattening pressure PF
C     with int_u0^u1 alpha1'(P cosh v) cosh v sinh(v)**2 / W dv = D
C     ({{ zp }}FPAN's W with G = P/s0, SL = tan(theta)),
C     P0 = P cosh(u0), PF = P cosh(u1) (CAP where the strain reaches
C     full contact), by Newton's method (the first step in w =
C     sinh(u)**3/3, then in u), each step's interval by {{ zp }}FQUAD,
C     bisection where a step leaves the bracket; DADP = d alpha1(PF)/
C     dP of the update, (D + S2) W(u1)/(cosh u1 sinh u1), S2 the
C     second integral of {{ zp }}FPAN from u0 to u1; AP = alpha1(PF),
C     which W(u1) needs too.
C=======================================================================
      SUBROUTINE {{ zp }}FSOLV(P, P0, D, CAP, G, SL, CMX, PF, DADP, AP)
      IMPLICIT NONE
      DOUBLE PRECISION P, P0, D, CAP, G, SL, CMX, PF, DADP, AP
      DOUBLE PRECISION U0, UCAP, U, F, XIC, XLO, XHI, R, CH, SH, A, DA
      DOUBLE PRECISION VC, {{ zp }}FSWTC
      EXTERNAL {{ zp }}FSWTC
      DOUBLE PRECISION CL, XL, W
      DOUBLE PRECISION UN, WN, DF, DI, FN, XIN, STEP
      INTEGER IT
      LOGICAL HICHK, HAVE
      U0 = ACOSH(MAX(P0/P, 1.0D0))
      UCAP = ACOSH(CAP/P)
      VC = {{ zp }}FSWTC(P, P0, CAP, SL, CMX)
      U = U0
      F = 0.0D0
      XIC = 0.0D0
      XLO = U0
      XHI = UCAP
      HICHK = .FALSE.
      DO IT = 0, 199
        R = D - F
        IF (IT .GT. 0 .AND. ABS(R) .LE. 1.0D-15*D) EXIT
        CH = COSH(U)
        SH = SINH(U)
        CALL {{ zp }}A1D(P*CH, A, DA)
        CALL {{ zp }}FRATE(SL, A, CMX, CL, XL)
        W = 1.0D0 + G*CH*SH*CL
        DA = DA/W
        HAVE = .FALSE.
        UN = 0.0D0
        IF (IT .EQ. 0) THEN
          IF (DA .GT. 0.0D0) THEN
            WN = SH*SH*SH/3.0D0 + R/DA
            IF (WN .GT. 0.0D0) THEN
              UN = ASINH((3.0D0*WN)**(1.0D0/3.0D0))
              HAVE = .TRUE.
            END IF
          END IF
        ELSE IF (DA .GT. 0.0D0) THEN
          UN = U + R/(DA*CH*SH*SH)
          HAVE = .TRUE.
          IF (ABS(UN - U) .LE. 1.0D-7*(1.0D0 + U) .AND.
     &        XLO .LT. UN .AND. UN .LT. XHI) THEN
C           the last step: the integrand is linear over it to below
C           1D-13, so F + R and the tangent's integral by its value at U
            XIC = XIC + (UN - U)*DA*CH*(1.0D0 - XL*G*CL*CH*SH*SH*SH)/W
            U = UN
            EXIT
          END IF
        END IF
        IF (.NOT. (HAVE .AND. UN .LT. XHI)) THEN
          IF (.NOT. HICHK) THEN
            UN = XHI
          ELSE
            UN = 0.5D0*(XLO + XHI)
          END IF
        ELSE IF (.NOT. (UN .GT. XLO) .OR.
     &           (MOD(IT, 8) .EQ. 7 .AND. HICHK)) THEN
          UN = 0.5D0*(XLO + XHI)
        END IF
        CALL {{ zp }}FQUAD(P, U, UN, G, SL, CMX, VC, DF, DI)
        FN = F + DF
        XIN = XIC + DI
        IF (UN .EQ. UCAP .AND. .NOT. HICHK) THEN
          IF (.NOT. (FN .GT. D)) THEN
            PF = CAP
            DADP = 0.0D0
            CALL {{ zp }}A1D(CAP, AP, DA)
            RETURN
          END IF
          HICHK = .TRUE.
        END IF
        IF (FN .LT. D) THEN
          XLO = UN
        ELSE
          XHI = UN
          HICHK = .TRUE.
        END IF
        STEP = ABS(UN - U)
        U = UN
        F = FN
        XIC = XIN
        IF (STEP .LE. 1.0D-14*(1.0D0 + U)) EXIT
        IF (HICHK .AND. XHI - XLO .LE. 1.0D-14*(1.0D0 + XHI)) EXIT
      END DO
      CH = COSH(U)
      PF = MIN(P*CH, CAP)
      IF (.NOT. (PF .LT. CAP)) THEN
        PF = CAP
        DADP = 0.0D0
        CALL {{ zp }}A1D(CAP, AP, DA)
        RETURN
      END IF
      SH = SINH(U)
      CALL {{ zp }}A1D(PF, AP, DA)
      CALL {{ zp }}FRATE(SL, AP, CMX, CL, XL)
      W = 1.0D0 + G*CH*SH*CL
      DADP = (D + XIC)*W/(CH*SH)
      RETURN
      END
C
C=======================================================================
C     One contact point's flattening over the increment (Eq. F6): from
C     the committed flattened fraction AF and history PH, at the
C     pressure P with the bulk's plastic strain increment DEPS (and
C     flow stress SIGY, <= 0: the file's sigma_y; hardening modulus
C     HMOD, d sigma_y / d eps_eq, <= 0: perfectly plastic, which
C     limits the lattice's rate to 6 P (1 - A) / HMOD, Eq. F2c): P0 =
C     max(p_f, PH, P) (p_f the pressure whose alpha1 is AF), then F6,
C     held at alpha1(max(PH, P)) + HSK P / (HMOD SLOPE) (Eq. F2d; PF
C     then 0).
C     ANEW: the trial fraction (never below AF); PF: its flattening
C     pressure where it was needed and the point is flattened beyond
C     max(PH, P), else 0; DADP: the update's d alpha/dP (0 without
C     one).
C     DEPS <= 0, P <= 1D-12 H and full contact leave AF as it is.
C=======================================================================
      SUBROUTINE {{ zp }}FLAT(P, PH, AF, DEPS, SIGY, HMOD, ANEW, PF,
     &                        DADP)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, AF, DEPS, SIGY, HMOD, ANEW, PF, DADP
      DOUBLE PRECISION P0, A0, D0, S0, X, DD, PP, DA, AP, CMX, HK
      DOUBLE PRECISION {{ zp }}FINV
      EXTERNAL {{ zp }}FINV
      DOUBLE PRECISION H, SLOPE, BETA, STR, S0F, SIGYF, CAP, PMIN
      PARAMETER (H = {{ law.H | double }})
      PARAMETER (SLOPE = {{ flat.slope | double }})
      PARAMETER (BETA = {{ flat.beta | double }})
      PARAMETER (STR = {{ flat.stretch | double }})
      PARAMETER (S0F = {{ flat.s0 | double }})
      PARAMETER (SIGYF = {{ flat.sigma_y | double }})
      PARAMETER (CAP = {{ flat.cap | double }})
      PARAMETER (PMIN = {{ flat.p_min | double }})
      DOUBLE PRECISION HSK
      PARAMETER (HSK = {{ flat.sink | double }})
      ANEW = AF
      PF = 0.0D0
      DADP = 0.0D0
      IF (.NOT. (DEPS .GT. 0.0D0 .AND. P .GT. PMIN)) RETURN
      P0 = MAX(PH, P)
      IF (AF .GT. 0.0D0) THEN
        CALL {{ zp }}A1D(P0, A0, D0)
        IF (AF .GT. A0) THEN
          P0 = {{ zp }}FINV(AF, P0, CAP)
          PF = P0
        END IF
      END IF
      IF (.NOT. (P0 .LT. CAP)) RETURN
      S0 = S0F
      IF (SIGY .GT. 0.0D0) S0 = S0F*(SIGY/SIGYF)
      X = P/H
      DD = DEPS*STR*BETA*(S0/H)/(SLOPE*X*X)/H
      CMX = HUGE(1.0D0)
      IF (HMOD .GT. 0.0D0) CMX = 6.0D0*P/HMOD
      CALL {{ zp }}FSOLV(P, P0, DD, CAP, P/S0, SLOPE, CMX, PP, DA, AP)
      IF (HMOD .GT. 0.0D0) THEN
        CALL {{ zp }}A1D(MAX(PH, P), A0, D0)
        HK = HSK/(HMOD*SLOPE)
        IF (A0 + HK*P .LT. 1.0D0 .AND. AP .GT. A0 + HK*P) THEN
          AP = A0 + HK*P
          PP = 0.0D0
          DA = HK
          IF (P .GE. PH) DA = HK + D0
        END IF
      END IF
      IF (AP .GT. AF) THEN
        ANEW = AP
        PF = PP
        DADP = DA
      END IF
      RETURN
      END
{% endif %}
C
C=======================================================================
C     Eq. F5 at the trial fraction ANEW (DADP its d alpha/dP, PF its
C     flattening pressure where the update found it above PH, else 0):
C     for P >= PH the larger of TMAX alpha1(P) and TMAX ANEW (DTAU the
C     update's there); below PH the law itself where ANEW <=
C     alpha1(PH), else its reload branch of the level p_f (alpha1(p_f)
C     = ANEW) at P p_f/PH (DTAU at that fixed level). G1OUT: the cache
C     value for max(PH, P) where it is known, else G1H.
C=======================================================================
      SUBROUTINE {{ zp }}FF5(P, PH, ANEW, PF, DADP, G1H, TAU, DTAU,
     &                       G1OUT)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, ANEW, PF, DADP, G1H, TAU, DTAU, G1OUT
      DOUBLE PRECISION T1, D1, G1, TA, AH, DH, G1X, PFL
      DOUBLE PRECISION {{ zp }}FINV
      EXTERNAL {{ zp }}FINV
      DOUBLE PRECISION TMAX, CAP
      PARAMETER (TMAX = {{ law.TMAX | double }})
      PARAMETER (CAP = {{ flat.cap | double }})
      IF (P .GE. PH) THEN
        CALL {{ zp }}FIRST(P, T1, D1, G1)
        G1OUT = G1
        TA = TMAX*ANEW
        IF (TA .GT. T1) THEN
          TAU = TA
          DTAU = TMAX*DADP
        ELSE
          TAU = T1
          DTAU = D1
        END IF
        RETURN
      END IF
      CALL {{ zp }}A1D(PH, AH, DH)
      IF (.NOT. (ANEW .GT. AH)) THEN
        CALL {{ zp }}SHEAR(P, PH, G1H, TAU, DTAU, G1OUT)
        RETURN
      END IF
      PFL = PF
      IF (.NOT. (PFL .GT. PH)) PFL = {{ zp }}FINV(ANEW, PH, CAP)
      G1OUT = G1H
      CALL {{ zp }}RELOAD((P/PH)*PFL, PFL, -1.0D0, TAU, DTAU, G1X)
      DTAU = DTAU*(PFL/PH)
      RETURN
      END
C
{% if flat.limit %}
{% include "core/sbmf_limit.f" %}
{% else %}
C=======================================================================
C     The shear limit with the flattening (Eqs. F5, F6): without strain
C     on a surface never flattened (DEPS <= 0, AF = 0), and for P <= 0,
C     {{ zp }}SHEAR itself. Otherwise the trial fraction ANEW of
C     {{ zp }}FLAT, then F5 ({{ zp }}FF5).
C=======================================================================
      SUBROUTINE {{ zp }}FSHR(P, PH, AF, DEPS, SIGY, HMOD, G1H, TAU,
     &                        DTAU, G1OUT, ANEW)
      IMPLICIT NONE
      DOUBLE PRECISION P, PH, AF, DEPS, SIGY, HMOD, G1H, TAU, DTAU
      DOUBLE PRECISION G1OUT
      DOUBLE PRECISION ANEW, PF, DADP
      ANEW = AF
      IF (.NOT. (P .GT. 0.0D0) .OR.
     &    (.NOT. (DEPS .GT. 0.0D0) .AND. AF .EQ. 0.0D0)) THEN
        CALL {{ zp }}SHEAR(P, PH, G1H, TAU, DTAU, G1OUT)
        RETURN
      END IF
      CALL {{ zp }}FLAT(P, PH, AF, DEPS, SIGY, HMOD, ANEW, PF, DADP)
      CALL {{ zp }}FF5(P, PH, ANEW, PF, DADP, G1H, TAU, DTAU, G1OUT)
      RETURN
      END
C
{% endif %}
