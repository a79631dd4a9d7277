C=======================================================================
C     Host-neutral entry point, to be called from the host's friction
C     template (see the README): one contact point per call.
C     In:  ND (1 or 2 tangential directions), P (contact pressure),
C          PH (committed p_hist), G1H (committed cache -ln alpha1(PH),
C          or <= 0: recompute),
C          DU(ND) (slip increment since the last converged state),
C          TOLD(ND) (traction of the last converged state),
C          KHOST (the host's tangential penalty, used only when the
C          parameter file has no calibrated k_t and no --k-t was given),
C          IUNIT (the unit system the deck states: 1 SI (Pa, m),
C          2 mm-t-s (MPa, mm); 0: the deck states none).
C     Out: TNEW(ND), DTDDU(ND,ND), DTDP(ND), ISTAT (0 open, 1 stick,
C          2 slip), PHNEW, G1NEW: the trial state; the caller stores
C          it only when the host accepts (converges) the increment.
C          IERR, the guards' status, which the caller must check:
C          0 fine; < 0 an error, the caller must stop the analysis:
C          -2 IUNIT = 0 (no unit system stated), -3 IUNIT is not the
C          unit system this routine was exported for, -6 PH > 100 H
C          (a converged pressure: the deck's units are not the
C          routine's), -4 P > 100 H (the same for an explicit caller;
C          an implicit caller, whose P may be a Newton iterate, should
C          take a smaller substep instead); 5 a warning: the first P
C          beyond the calibrated range in this process (once per
C          process). The outputs are the law's in every case.
C          CALL SBMF_MESSAGE(ABS(IERR), XV, MSG, NMSG) gives the text
C          (XV: DBLE(IUNIT) for -3, P for -4 and 5, PH for -6; MSG
C          CHARACTER*400).
C=======================================================================
      SUBROUTINE SBMF_FRICTION(ND, P, PH, G1H, DU, TOLD, KHOST, IUNIT,
     &                         TNEW, DTDDU, DTDP, ISTAT, PHNEW, G1NEW,
     &                         IERR)
      IMPLICIT NONE
      INTEGER ND, ISTAT, A, B, IUNIT, IERR
      DOUBLE PRECISION P, PH, G1H, DU(ND), TOLD(ND), KHOST, TNEW(ND)
      DOUBLE PRECISION DTDDU(ND, ND), DTDP(ND), PHNEW, G1NEW
      DOUBLE PRECISION TLIM, DTAU, XKT
      DOUBLE PRECISION SBMF_KT
      INTEGER SBMF_ONCE
      EXTERNAL SBMF_KT, SBMF_ONCE
{% include "core/guard_decl.f" %}
      IERR = 0
{% if guards %}
C     guards: the stated unit system, the pressure (the caller reports)
      IF (IUNIT .EQ. 0) THEN
        IERR = -2
      ELSE IF (DBLE(IUNIT) .NE. SBMFU) THEN
        IERR = -3
      ELSE IF (PH .GT. SBMFPU) THEN
        IERR = -6
      ELSE IF (P .GT. SBMFPU) THEN
        IERR = -4
      ELSE IF (P .GT. SBMFPM) THEN
        IF (SBMF_ONCE(5) .EQ. 1) IERR = 5
      END IF
{% endif %}
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
