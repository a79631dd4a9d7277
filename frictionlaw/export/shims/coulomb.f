C     The benchmark's floor: a Coulomb law (mu = 0.1) behind the entries
C     of the host-neutral routine (SBMF_FRICTION_V, the deprecated
C     SBMF_FRICTION wrapper, SBMF_ZMESSAGE), with the same calls.
      SUBROUTINE SBMF_FRICTION_V(IVERS, ZONE, ND, P, DU, TOLD, KHOST,
     &                           IUNIT, DEPS, SIGY, NSTATE, STATE,
     &                           TNEW, DTDDU, DTDP, ISTAT, IERR)
      IMPLICIT NONE
      INTEGER IVERS, ND, IUNIT, NSTATE, ISTAT, IERR, A, B
      CHARACTER*(*) ZONE
      DOUBLE PRECISION P, DU(ND), TOLD(ND), KHOST, DEPS, SIGY
      DOUBLE PRECISION STATE(NSTATE), TNEW(ND), DTDDU(ND, ND), DTDP(ND)
      DOUBLE PRECISION TLIM, XMU
      PARAMETER (XMU = 0.1D0)
      IERR = 0
      IF (IVERS .NE. 2) IERR = -8
      IF (ZONE .EQ. 'X' .AND. DEPS .LT. SIGY) CONTINUE
      IF (IUNIT .LT. 0) IERR = -2
      IF (.NOT. (P .GT. 0.0D0)) THEN
        DO A = 1, ND
          TNEW(A) = 0.0D0
          DTDP(A) = 0.0D0
          DO B = 1, ND
            DTDDU(A, B) = 0.0D0
          END DO
        END DO
        ISTAT = 0
        RETURN
      END IF
      TLIM = XMU*P
      CALL SBMF_RMAP(ND, TLIM, XMU, DU, TOLD, KHOST, TNEW, DTDDU, DTDP,
     &               ISTAT)
      IF (NSTATE .GE. 1) STATE(1) = MAX(STATE(1), P)
      RETURN
      END
C
{% include "neutral/sbmf_friction_v1.f" %}
      SUBROUTINE SBMF_ZMESSAGE(NAME, MSG, NMSG)
      IMPLICIT NONE
      CHARACTER*(*) NAME, MSG
      INTEGER NMSG
      MSG = 'Coulomb floor: ' // NAME
      NMSG = LEN_TRIM(MSG)
      RETURN
      END
C
{% include "core/sbmf_core.f" %}
