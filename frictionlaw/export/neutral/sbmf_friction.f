C=======================================================================
C     Host-neutral entry point, to be called from the host's friction
C     template (see the README): one contact point per call.
C     In:  ND (1 or 2 tangential directions), P (contact pressure),
C          PH (committed p_hist), G1H (committed cache -ln alpha1(PH),
C          or <= 0: recompute),
C          DU(ND) (slip increment since the last converged state),
C          TOLD(ND) (traction of the last converged state),
C          KHOST (the host's tangential penalty, used only when the
C          parameter file has no calibrated k_t and no --k-t was given).
C     Out: TNEW(ND), DTDDU(ND,ND), DTDP(ND), ISTAT (0 open, 1 stick,
C          2 slip), PHNEW, G1NEW: the trial state; the caller stores
C          it only when the host accepts (converges) the increment.
C=======================================================================
      SUBROUTINE SBMF_FRICTION(ND, P, PH, G1H, DU, TOLD, KHOST, TNEW,
     &                         DTDDU, DTDP, ISTAT, PHNEW, G1NEW)
      IMPLICIT NONE
      INTEGER ND, ISTAT, A, B
      DOUBLE PRECISION P, PH, G1H, DU(ND), TOLD(ND), KHOST, TNEW(ND)
      DOUBLE PRECISION DTDDU(ND, ND), DTDP(ND), PHNEW, G1NEW
      DOUBLE PRECISION TLIM, DTAU, XKT
      DOUBLE PRECISION SBMF_KT
      EXTERNAL SBMF_KT
      IF (.NOT. (P .GT. 0.0D0)) THEN
        DO A = 1, ND
          TNEW(A) = 0.0D0
          DTDP(A) = 0.0D0
          DO B = 1, ND
            DTDDU(A, B) = 0.0D0
          END DO
        END DO
        ISTAT = 0
        PHNEW = PH
        G1NEW = G1H
        RETURN
      END IF
      CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
      XKT = SBMF_KT(P, KHOST)
      CALL SBMF_RMAP(ND, TLIM, DTAU, DU, TOLD, XKT, TNEW, DTDDU, DTDP,
     &               ISTAT)
      PHNEW = MAX(PH, P)
      RETURN
      END
C
{% include "core/sbmf_core.f" %}
