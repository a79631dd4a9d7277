{#
  The host-neutral entry of interface version 1, SBMF_FRICTION: deprecated, kept for one
  release as a thin wrapper of SBMF_FRICTION_V (interface version 2). Included by
  neutral/sbmf_friction.f and by the benchmark's Coulomb floor (shims/coulomb.f), so that both
  pay the same wrapper. Context: zones (None for one law).
#}
C=======================================================================
C     DEPRECATED (interface version 1; kept for one release): the entry
C     of earlier exports, a thin wrapper of SBMF_FRICTION_V with a
C     blank ZONE ({% if zones %}{% if zones.default %}the default law{% else %}no law: IERR = -7{% endif %}{% else %}the routine's one law{% endif %}), no bulk strain, the
C     state PH, G1H in (committed) and PHNEW, G1NEW out (trial).
C     IERR as SBMF_FRICTION_V's. New callers: SBMF_FRICTION_V.
C=======================================================================
      SUBROUTINE SBMF_FRICTION(ND, P, PH, G1H, DU, TOLD, KHOST, IUNIT,
     &                         TNEW, DTDDU, DTDP, ISTAT, PHNEW, G1NEW,
     &                         IERR)
      IMPLICIT NONE
      INTEGER ND, ISTAT, IUNIT, IERR
      DOUBLE PRECISION P, PH, G1H, DU(ND), TOLD(ND), KHOST, TNEW(ND)
      DOUBLE PRECISION DTDDU(ND, ND), DTDP(ND), PHNEW, G1NEW
      DOUBLE PRECISION STATE(3)
      STATE(1) = PH
      STATE(2) = G1H
      STATE(3) = 0.0D0
      CALL SBMF_FRICTION_V(2, ' ', ND, P, DU, TOLD, KHOST, IUNIT,
     &                     0.0D0, 0.0D0, 3, STATE, TNEW, DTDDU, DTDP,
     &                     ISTAT, IERR)
      PHNEW = STATE(1)
      G1NEW = STATE(2)
      RETURN
      END
C
