C=======================================================================
C     LS-DYNA MPP user friction usrfrc (argument list of the MPP sample
C     in LSTC's user file dyn21.F): one slave node per call, returns
C     friction coefficients. Coefficient form of the law: FSTT = FDYN =
C     tau(p, p_hist)/p with p = PRS (interface pressure, > 0 in
C     contact); LS-DYNA applies them in its own Coulomb return map.
C     UH(1) = p_hist (NH >= 1; stored rounded down to the host REAL),
C     UH(2) = cache -ln alpha1(p_hist) (NH >= 2, double hosts only).
C     PRS <= 0: FSTT = FDYN = 0, history unchanged. Host arguments have
C     the host's default REAL/INTEGER (see the SMP routine).
C=======================================================================
      SUBROUTINE USRFRC(FSTT,FDYN,UC,NC,PRS,TEMP,V,UH,NH,CRV,NNPCRV,
     & NOSL,ICTYPE,SIDE,TIME,NCYCLE,DT2,FRIC1,FRIC2,FRIC3,FRIC4,LSV,
     & IDELE8,SFAC1,SFAC2,INSV,FNI,AREAS,STFK,IX1,IX2,IX3,IX4,AREAM,
     & RN1,RN2,RN3,UE,NE)
      IMPLICIT NONE
      REAL FSTT, FDYN
      INTEGER NC, NH, NOSL, ICTYPE, NCYCLE, LSV, INSV, NE
      INTEGER IX1, IX2, IX3, IX4
      REAL UC(*), UH(*), UE(*), CRV(*)
      REAL PRS, TEMP, V, TIME, DT2, FRIC1, FRIC2, FRIC3, FRIC4
      REAL SFAC1, SFAC2, FNI, AREAS, STFK, AREAM, RN1, RN2, RN3
      INTEGER NNPCRV(*)
      CHARACTER*(*) SIDE
      INTEGER*8 IDELE8
C
      DOUBLE PRECISION P, PH, PHNEW, G1H, G1NEW, TLIM, DTAU, XMU, HR
      REAL RPH
      LOGICAL USECAC
      HR = DBLE(HUGE(RPH))
      USECAC = (KIND(RPH) .EQ. KIND(HR)) .AND. (NH .GE. 2)
      P = DBLE(PRS)
      IF (.NOT. (P .GT. 0.0D0)) THEN
        FSTT = 0.0
        FDYN = 0.0
        RETURN
      END IF
      PH = 0.0D0
      IF (NH .GE. 1) PH = MAX(DBLE(UH(1)), 0.0D0)
      G1H = -1.0D0
      IF (USECAC) G1H = DBLE(UH(2))
      CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
      XMU = MIN(TLIM/P, HR)
      FSTT = REAL(XMU)
      FDYN = FSTT
      PHNEW = MAX(PH, P)
      IF (NH .GE. 1) THEN
        RPH = REAL(MIN(PHNEW, HR))
        IF (DBLE(RPH) .GT. PHNEW) RPH = NEAREST(RPH, -1.0)
        UH(1) = RPH
      END IF
      IF (USECAC) UH(2) = REAL(G1NEW)
      RETURN
      END
C
{% include "core/sbmf_core.f" %}
