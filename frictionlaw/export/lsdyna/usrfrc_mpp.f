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
C     UC(1), the first user parameter (NC >= 1), states the deck's unit
C     system: 1 SI (Pa, m), 2 mm-t-s (MPa, mm). Guards (docs/
C     fe_codes.md): NH >= 1, UC(1) = the unit system this routine was
C     exported for, p <= 100 H, else FSTT = FDYN = 0 (no friction,
C     history unchanged) with one message per process (terminal,
C     d3hsp, messag: iounits.inc); p beyond the calibrated range: one
C     warning per process.
{% if flat %}
C     Flattening under bulk strain (the file's flattening block): the
C     slave node's element plastic strain UE(1) (NE >= 1), its
C     increment since the last cycle in contact, UH(5) = the flattened
C     contact fraction, UH(6) = the plastic strain and UH(7) =
C     MOD(cycle, 2**20) + 1 of the last call in contact{% if flat.limit %}, UH(8) =
C     the asperities' flank slope (the two-state model){% endif %} (NH >= {{ flat_states }}).
C     Without them the law runs without flattening, said once.
{% endif %}
{% if zones %}
C     Zones: the law of the interface number NOSL ({{ zones.laws | length }} laws);
C     {% if zones.default %}an interface no zone gives runs the default law{% else %}an interface no zone gives: no friction on it and one
C     message (no default law){% endif %}. UH(4) = the
C     law that wrote the cache (NH >= 4); p_hist carries over.
{% endif %}
{% from "core/zone_pick.f" import pick with context %}
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
{% if flat %}
      DOUBLE PRECISION AF, ANEW, DEPS, SIGY, HMOD
{% if flat.limit %}
      DOUBLE PRECISION SF, SNEW
{% endif %}
{% if flow %}
      DOUBLE PRECISION EM
{% endif %}
      REAL RA
{% endif %}
{% if zones %}
      CHARACTER*12 ZNAME
      INTEGER SBMF_ZONEN
      EXTERNAL SBMF_ZONEN
{% endif %}
{% include "core/guard_decl.f" %}
      HR = DBLE(HUGE(RPH))
      USECAC = (KIND(RPH) .EQ. KIND(HR)) .AND. (NH .GE. 2)
      P = DBLE(PRS)
      FSTT = 0.0
      FDYN = 0.0
{% if zones %}
{% call pick("SBMF_ZONEN(NOSL)", "ZNAME", "WRITE (ZNAME, '(I0)') NOSL") %}
        RETURN
{% endcall %}
      USECAC = USECAC .AND. (NH .GE. 4)
{% endif %}
{% if guards %}
C     guards: a failed one refuses the law (no friction, no history)
      IF (NH .LT. 1) THEN
        CALL SBMF_GUARD(1, DBLE(NH))
        RETURN
      ELSE IF (NC .LT. 1) THEN
        CALL SBMF_GUARD(2, 0.0D0)
        RETURN
      ELSE IF (DBLE(UC(1)) .NE. SBMFU) THEN
        CALL SBMF_GUARD(3, DBLE(UC(1)))
        RETURN
      ELSE IF (P .GT. SBMFPU) THEN
        CALL SBMF_GUARD(4{{ " + KZ" if zones else "" }}, P)
        RETURN
      END IF
      IF (P .GT. SBMFPM) CALL SBMF_GUARD(5{{ " + KZ" if zones else "" }}, P)
{% endif %}
      IF (.NOT. (P .GT. 0.0D0)) RETURN
      PH = 0.0D0
      IF (NH .GE. 1) PH = MAX(DBLE(UH(1)), 0.0D0)
      G1H = -1.0D0
{% if flat %}
{% if zones %}
      IF (USECAC) THEN
        IF (DBLE(UH(4)) .EQ. DBLE(IZ)) G1H = DBLE(UH(2))
      END IF
{% else %}
      IF (USECAC) G1H = DBLE(UH(2))
{% endif %}
      IF (NE .GE. 1 .AND. NH .GE. {{ flat_states }}) THEN
        AF = MIN(MAX(DBLE(UH(5)), 0.0D0), 1.0D0)
C       the strain since the last cycle, if the point was in contact
C       then (else it starts counting now)
        DEPS = 0.0D0
        IF (NINT(UH(7)) .EQ. MOD(NCYCLE - 1, 1048576) + 1)
     &    DEPS = MAX(DBLE(UE(1)) - DBLE(UH(6)), 0.0D0)
{% if flow %}
C       the flow stress and hardening modulus off the workpiece's flow
C       curve, at the middle of the cycle's strain
        EM = MAX(DBLE(UE(1)) - 0.5D0*DEPS, 0.0D0)
        CALL SBMF_FLOW(EM, SIGY, HMOD)
{% else %}
C       no flow curve: the file's sigma_y, perfectly plastic
        SIGY = 0.0D0
        HMOD = 0.0D0
{% endif %}
{% if flat.limit %}
C       the two-state model (perfectly plastic)
        SF = DBLE(UH(8))
        CALL {{ "SBMF_ZTSHR(IZ, " if zones else "SBMF_TSHR(" }}P, PH, AF, SF, DEPS,
     &       SIGY, G1H, TLIM, DTAU, G1NEW, ANEW, SNEW)
C       HMOD: the one-state model's, set above and not read here
        IF (HMOD .LT. 0.0D0) CONTINUE
        UH(8) = REAL(SNEW)
{% else %}
        CALL {{ "SBMF_ZFSHR(IZ, " if zones else "SBMF_FSHR(" }}P, PH, AF, DEPS, SIGY, HMOD, G1H, TLIM,
     &                 DTAU, G1NEW, ANEW)
{% endif %}
        RA = REAL(ANEW)
        UH(5) = RA
        UH(6) = UE(1)
        UH(7) = REAL(MOD(NCYCLE, 1048576) + 1)
      ELSE
{% if guards %}
        CALL SBMF_GUARD(9, 0.0D0)
{% endif %}
        CALL {{ "SBMF_ZSHEAR(IZ, " if zones else "SBMF_SHEAR(" }}P, PH, G1H, TLIM, DTAU, G1NEW)
      END IF
{% elif zones %}
      IF (USECAC) THEN
        IF (DBLE(UH(4)) .EQ. DBLE(IZ)) G1H = DBLE(UH(2))
      END IF
      CALL SBMF_ZSHEAR(IZ, P, PH, G1H, TLIM, DTAU, G1NEW)
{% else %}
      IF (USECAC) G1H = DBLE(UH(2))
      CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
{% endif %}
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
{% if zones %}
      IF (USECAC) UH(4) = REAL(IZ)
{% endif %}
      RETURN
      END
C
{% include host.guards %}
{% include "core/sbmf_core.f" %}
{% if flow %}
{% include "core/sbmf_flow.f" %}
{% endif %}
