      SUBROUTINE SBMF_FRICTION(ND, P, PH, G1H, DU, TOLD, KHOST, IUNIT,
     &                         TNEW, DTDDU, DTDP, ISTAT, PHNEW, G1NEW,
     &                         IERR)
      IMPLICIT NONE
      INTEGER ND, ISTAT, A, B, IUNIT, IERR
      DOUBLE PRECISION P, PH, G1H, DU(ND), TOLD(ND), KHOST, TNEW(ND)
      DOUBLE PRECISION DTDDU(ND, ND), DTDP(ND), PHNEW, G1NEW, TLIM, XMU
      PARAMETER (XMU = 0.1D0)
      PHNEW = PH
      G1NEW = G1H
      IERR = 0
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
      RETURN
      END
C
{% include "core/sbmf_core.f" %}
