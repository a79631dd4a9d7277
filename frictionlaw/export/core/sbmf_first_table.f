{#
  The tabulated first loading's part of the law core (frictionlaw.first_loading), included by
  core/sbmf_core.f in place of Eq. 24's {{ zp }}FIRST when the parameter file selects
  first_loading_form = "tabulated" (the template its record names,
  frictionlaw.forms.BranchForm.export_template): {{ zp }}LRAT (frictionlaw._kernels.log_ratio),
  {{ zp }}FTAB (first_table_log), {{ zp }}LNA1 (ln_alpha1) and {{ zp }}FIRST
  (sbmf_first_table_scalar), statement by statement. Rendered with core/sbmf_core.f's values
  (frictionlaw.export._law.core_context): law, first (the FirstSpec: the knots u = ln(p_j/H),
  v = ln alpha_j and the slopes d = dv/du as PARAMETER arrays, exactly the runtime's
  coefficient block; the Coulomb slope XMU below the lowest level), ln_h.
#}
C=======================================================================
C     ln(P/H) for P > 0 (frictionlaw's log_ratio): one log of the
C     quotient where it is a normal double, else ln P - ln H.
C=======================================================================
      DOUBLE PRECISION FUNCTION {{ zp }}LRAT(P)
      IMPLICIT NONE
      DOUBLE PRECISION P, X
      DOUBLE PRECISION H, LNH
      PARAMETER (H = {{ law.H | double }})
C     ln H, as the runtime's log(H) gives it
      PARAMETER (LNH = {{ ln_h | double }})
      X = P/H
      IF (1.0D-300 .LT. X .AND. X .LT. 1.0D+300) THEN
        {{ zp }}LRAT = LOG(X)
      ELSE
        {{ zp }}LRAT = LOG(P) - LNH
      END IF
      RETURN
      END
C
C=======================================================================
C     (ln alpha1, d ln alpha1/d ln P) of the tabulated first loading at
C     LNQ = ln(P/H) (frictionlaw's first_table_log): below the lowest
C     level the Coulomb line V(1) + (LNQ - U(1)) (slope 1); between
C     the levels the monotone cubic Hermite interpolant (Fritsch-
C     Carlson slopes) of ln alpha over ln(p/H) through the computed
C     first loading; above the top level the power law of its end
C     slope, V(NJ) + D(NJ) (LNQ - U(NJ)), capped at ln alpha = 0
C     (slope 0 there).
C=======================================================================
      SUBROUTINE {{ zp }}FTAB(LNQ, LNA, S)
      IMPLICIT NONE
      DOUBLE PRECISION LNQ, LNA, S
      DOUBLE PRECISION HK, T, W, Y0, Y1, D0, D1
      INTEGER J, NJ
      PARAMETER (NJ = {{ first.u | length }})
      DOUBLE PRECISION UK(NJ), VK(NJ), DK(NJ)
{% for name, values in (("UK", first.u), ("VK", first.v), ("DK", first.d)) %}
      PARAMETER ({{ name }} = (/
     &  {{ values | map("double") | join(",
     &  ") }} /))
{% endfor %}
      IF (.NOT. (LNQ .GT. UK(1))) THEN
        LNA = VK(1) + (LNQ - UK(1))
        S = 1.0D0
        RETURN
      END IF
      IF (.NOT. (LNQ .LT. UK(NJ))) THEN
        S = DK(NJ)
        IF (S .EQ. 0.0D0) THEN
          LNA = MIN(VK(NJ), 0.0D0)
          RETURN
        END IF
        LNA = VK(NJ) + S*(LNQ - UK(NJ))
        IF (.NOT. (LNA .LT. 0.0D0)) THEN
          LNA = 0.0D0
          S = 0.0D0
        END IF
        RETURN
      END IF
      J = 1
   10 IF (J .LT. NJ - 1 .AND. LNQ .GE. UK(J + 1)) THEN
        J = J + 1
        GOTO 10
      END IF
      HK = UK(J + 1) - UK(J)
      T = (LNQ - UK(J))/HK
      W = 1.0D0 - T
      Y0 = VK(J)
      Y1 = VK(J + 1)
      D0 = DK(J)
      D1 = DK(J + 1)
      LNA = (1.0D0 + 2.0D0*T)*W*W*Y0 + T*W*W*HK*D0
     &    + T*T*(3.0D0 - 2.0D0*T)*Y1
      LNA = LNA + T*T*(T - 1.0D0)*HK*D1
C     d/dLNQ: dh00/dt = 6t(t - 1) = -dh01/dt, dh10/dt = w(1 - 3t),
C     dh11/dt = t(3t - 2)
      S = 6.0D0*T*(T - 1.0D0)*(Y0 - Y1)/HK + W*(1.0D0 - 3.0D0*T)*D0
     &  + T*(3.0D0*T - 2.0D0)*D1
      LNA = MIN(LNA, 0.0D0)
      RETURN
      END
C
C     ln alpha1(PH), PH > 0, of the tabulated first loading
C     (frictionlaw's ln_alpha1): what the reload branch is scaled by,
C     and the cache -ln alpha1(p_hist) negated.
      DOUBLE PRECISION FUNCTION {{ zp }}LNA1(PH)
      IMPLICIT NONE
      DOUBLE PRECISION PH, S
      DOUBLE PRECISION {{ zp }}LRAT
      EXTERNAL {{ zp }}LRAT
      CALL {{ zp }}FTAB({{ zp }}LRAT(PH), {{ zp }}LNA1, S)
      RETURN
      END
C
C=======================================================================
C     The tabulated first loading (frictionlaw's
C     sbmf_first_table_scalar), P > 0: TAU = TMAX alpha1(P), DTAU =
C     dTAU/dP = TAU (d ln alpha1/d ln P)/P, held below the largest
C     double; below the lowest level the Coulomb line TAU = XMU P,
C     XMU = TMAX alpha_0/p_0 (exact for every tiny P). G1 = the cache
C     value for p_hist = P, -ln alpha1(P) ({{ zp }}LNA1's statements).
C=======================================================================
      SUBROUTINE {{ zp }}FIRST(P, TAU, DTAU, G1)
      IMPLICIT NONE
      DOUBLE PRECISION P, TAU, DTAU, G1
      DOUBLE PRECISION LNQ, LNA, S
      DOUBLE PRECISION {{ zp }}LRAT
      EXTERNAL {{ zp }}LRAT
      DOUBLE PRECISION TMAX, U0, XMU
      PARAMETER (TMAX = {{ law.TMAX | double }})
      PARAMETER (U0 = {{ first.u[0] | double }})
C     TMAX exp(V(1) - U(1))/H, as the runtime forms it
      PARAMETER (XMU = {{ first.mu | double }})
      LNQ = {{ zp }}LRAT(P)
      CALL {{ zp }}FTAB(LNQ, LNA, S)
      G1 = -LNA
      IF (.NOT. (LNQ .GT. U0)) THEN
        TAU = P*XMU
        DTAU = XMU
        RETURN
      END IF
      TAU = TMAX*EXP(LNA)
      IF (S .EQ. 0.0D0) THEN
        DTAU = 0.0D0
      ELSE
        DTAU = MIN(TAU*S/P, HUGE(DTAU))
      END IF
      RETURN
      END
C
