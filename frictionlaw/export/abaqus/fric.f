C=======================================================================
C     Abaqus/Standard user subroutine FRIC (documented argument list).
C     STATEV(1) = p_hist (DEPVAR >= 1), STATEV(2) = cached
C     -ln alpha1(p_hist) (DEPVAR >= 2, optional), STATEV(3) = status of
C     the last call,
C     0 open 1 stick 2 slip (DEPVAR >= 3, optional, output only).
C     Abaqus passes STATEV and TAU as at the start of the increment and
C     keeps the values written here only when the increment converges:
C     p_hist therefore rises only through Abaqus' commit.
C     PROPS(1) (*FRICTION, USER, PROPERTIES=1 and its data line) states
C     the deck's unit system: 1 SI (Pa, m), 2 mm-t-s (MPa, mm).
C     Guards (docs/fe_codes.md): NSTATV >= 1, PROPS(1) = the unit
C     system this routine was exported for, PRESS <= 100 H, else an
C     error message ({{ host.message_routine }}) and {{ host.exit_routine }}; PRESS beyond
C     the calibrated range: one warning per process.
C=======================================================================
      SUBROUTINE FRIC(LM,TAU,DDTDDG,DDTDDP,DSLIP,SED,SFD,
     1 DDTDDT,PNEWDT,STATEV,DGAM,TAULM,PRESS,DPRESS,DDPDDH,SLIP,
     2 KSTEP,KINC,TIME,DTIME,NOEL,CINAME,SLNAME,MSNAME,NPT,NODE,
     3 NPATCH,COORDS,RCOORD,DROT,TEMP,PREDEF,NFDIR,MCRD,NPRED,
     4 NSTATV,CHRLNGTH,PROPS,NPROPS)
C
      INCLUDE 'ABA_PARAM.INC'
C
      CHARACTER*80 CINAME,SLNAME,MSNAME
C
      DIMENSION TAU(NFDIR),DDTDDG(NFDIR,NFDIR),DDTDDP(NFDIR),
     1 DSLIP(NFDIR),DDTDDT(NFDIR,2),STATEV(*),DGAM(NFDIR),
     2 TAULM(NFDIR),SLIP(NFDIR),TIME(2),COORDS(MCRD),
     3 RCOORD(MCRD),DROT(2,2),TEMP(2),PREDEF(2,*),PROPS(NPROPS)
C
      DOUBLE PRECISION P, PH, G1H, G1NEW, TLIM, DTAU, XKT, KFALL
      DOUBLE PRECISION TOLD(2), TNEW(2), DTDDU(2,2), DTDP(2)
      INTEGER ISTAT, IA, IB
      DOUBLE PRECISION SBMF_KT
      EXTERNAL SBMF_KT
C     elastic slip of Abaqus' own penalty friction: 0.005 CHRLNGTH
      DOUBLE PRECISION FSLIP
      PARAMETER (FSLIP = 5.0D-3)
{% include "core/guard_decl.f" %}
C
      P = PRESS
{% if guards %}
C     guards: the deck's state variables and unit system, the pressure
      IF (NSTATV .LT. 1) THEN
        CALL SBMF_GUARD(1, DBLE(NSTATV))
        RETURN
      END IF
      IF (NPROPS .LT. 1) THEN
        CALL SBMF_GUARD(2, 0.0D0)
        RETURN
      END IF
      IF (PROPS(1) .NE. SBMFU) THEN
        CALL SBMF_GUARD(3, PROPS(1))
        RETURN
      END IF
      IF (P .GT. SBMFPU) THEN
        CALL SBMF_GUARD(4, P)
        RETURN
      END IF
      IF (P .GT. SBMFPM) CALL SBMF_GUARD(5, P)
{% endif %}
      PH = STATEV(1)
      G1H = -1.0D0
      IF (NSTATV .GE. 2) G1H = STATEV(2)
      SED = 0.0D0
      SFD = 0.0D0
      DO IA = 1, NFDIR
        DSLIP(IA) = 0.0D0
        DDTDDP(IA) = 0.0D0
        DDTDDT(IA, 1) = 0.0D0
        DDTDDT(IA, 2) = 0.0D0
        DO IB = 1, NFDIR
          DDTDDG(IA, IB) = 0.0D0
        END DO
      END DO
      IF (.NOT. (P .GT. 0.0D0)) THEN
C       open (no pressure): no friction, history unchanged
        LM = 2
        DO IA = 1, NFDIR
          TAU(IA) = 0.0D0
        END DO
        IF (NSTATV .GE. 3) STATEV(3) = 0.0D0
        RETURN
      END IF
      CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
      KFALL = MAX(TLIM, TINY(1.0D0))/(FSLIP*CHRLNGTH)
      XKT = SBMF_KT(P, KFALL)
      DO IA = 1, NFDIR
        TOLD(IA) = TAU(IA)
      END DO
      CALL SBMF_RMAP(NFDIR, TLIM, DTAU, DGAM, TOLD, XKT, TNEW, DTDDU,
     &               DTDP, ISTAT)
      LM = 0
      DO IA = 1, NFDIR
        TAU(IA) = TNEW(IA)
        DDTDDP(IA) = DTDP(IA)
        DO IB = 1, NFDIR
          DDTDDG(IA, IB) = DTDDU(IA, IB)
        END DO
        IF (ISTAT .EQ. 2) THEN
          DSLIP(IA) = DGAM(IA) - (TNEW(IA) - TOLD(IA))/XKT
        END IF
        SED = SED + 0.5D0*TNEW(IA)*TNEW(IA)/XKT
        SFD = SFD + TNEW(IA)*DSLIP(IA)
      END DO
C     trial history max(p_hist, p): kept by Abaqus only if converged
      STATEV(1) = MAX(PH, P)
      IF (NSTATV .GE. 2) STATEV(2) = G1NEW
      IF (NSTATV .GE. 3) STATEV(3) = DBLE(ISTAT)
      RETURN
      END
C
C     The state variables FRIC needs (DEPVAR >= 1: STATEV(1) = p_hist).
C     The CalculiX patch checks DEPVAR against it when ccx reads the
C     deck; Abaqus does not call it.
      INTEGER FUNCTION FRIC_DEPVAR()
      IMPLICIT NONE
      FRIC_DEPVAR = 1
      RETURN
      END
C
{% include host.guards %}
{% include "core/sbmf_core.f" %}
