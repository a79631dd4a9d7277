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
C     system this routine was exported for, else an error message
C     ({{ host.message_routine }}) and {{ host.exit_routine }}. The pressure checks act on what
C     has converged: a committed p_hist (STATEV(1) at the start of the
C     increment) above 100 H stops the run, one beyond the calibrated
C     range gives one warning per process. An iterate's PRESS above
C     100 H asks for a smaller increment (PNEWDT) until the increment
C     is 1/{{ (1 / guard.cut_floor) | round | int }} of the size at which that first happened.
{% if flat and target.form.bulk_strain %}
C     Flattening under bulk strain (the file's flattening block): the
C     patched ccx passes the equivalent plastic strain under the point
C     (its solid elements' PEEQ) as the predefined field 1 (NPRED = 1;
C     PREDEF(1,1) at this iterate, PREDEF(2,1) its increment since the
C     start of the increment); STATEV(5) = the flattened contact
{% if flat.limit %}
C     fraction, STATEV(6) = the asperities' flank slope (the two-state
C     model) (DEPVAR >= {{ flat_states }}, FRIC_DEPVAR), trial values kept only when
{% else %}
C     fraction (DEPVAR >= {{ flat_states }}, FRIC_DEPVAR), a trial value kept only when
{% endif %}
C     the increment converges, as p_hist. NPRED = 0 (layered or beam
C     elements): the state kept, not grown, said once.
{% endif %}
{% if zones %}
C     Zones: the law of the name in {{ zones.key.argument }}, compared trimmed
C     and case-insensitive (SBMF_ZONE); {% if zones.default %}a name no zone gives
C     runs the default law{% else %}a name no zone gives stops
C     the run (no default law){% endif %}. STATEV(4) = the law that wrote
C     STATEV(2) (DEPVAR >= 4): the cache is used only under that law;
C     p_hist is the workpiece's and carries over from zone to zone.
{% endif %}
{% from "core/zone_pick.f" import pick with context %}
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
{% if flat and target.form.bulk_strain %}
      DOUBLE PRECISION AF, ANEW, DEPS, SIGY, HMOD
{% if flat.limit %}
      DOUBLE PRECISION SF, SNEW
{% endif %}
{% if flow %}
      DOUBLE PRECISION EM
{% endif %}
{% endif %}
      DOUBLE PRECISION TOLD(2), TNEW(2), DTDDU(2,2), DTDP(2)
      INTEGER ISTAT, IA, IB
{% if zones %}
      DOUBLE PRECISION SBMF_ZKT, SBMF_CUTS
      INTEGER SBMF_ZONE
      EXTERNAL SBMF_ZKT, SBMF_CUTS, SBMF_ZONE
{% else %}
      DOUBLE PRECISION SBMF_KT, SBMF_CUTS
      EXTERNAL SBMF_KT, SBMF_CUTS
{% endif %}
C     guards: the PNEWDT of an iterate above 100 H, and the fraction of
C     the increment's size below which no more is asked for
      DOUBLE PRECISION SBMFCB, SBMFCF
      PARAMETER (SBMFCB = {{ guard.cut_factor | double }})
      PARAMETER (SBMFCF = {{ guard.cut_floor | double }})
C     elastic slip of Abaqus' own penalty friction: 0.005 CHRLNGTH
      DOUBLE PRECISION FSLIP
      PARAMETER (FSLIP = 5.0D-3)
{% include "core/guard_decl.f" %}
C
      P = PRESS
{% if guards %}
C     guards: the deck's state variables and unit system
      IF (NSTATV .LT. 1) THEN
        CALL SBMF_GUARD(1, DBLE(NSTATV))
        RETURN
      END IF
      IF (NPROPS .LT. 1) THEN
        CALL SBMF_GUARD(2, 0.0D0)
        RETURN
      END IF
      IF (NPROPS .GT. 1) THEN
        CALL SBMF_GUARD(10, DBLE(NPROPS))
        RETURN
      END IF
      IF (PROPS(1) .NE. SBMFU) THEN
        CALL SBMF_GUARD(3, PROPS(1))
        RETURN
      END IF
{% if flat and not target.form.bulk_strain %}
C     the flattening block: no bulk strain reaches FRIC (a warning,
C     once per process; the law runs without it)
      CALL SBMF_GUARD(9, 0.0D0)
{% endif %}
{% endif %}
{% if zones %}
{% call pick("SBMF_ZONE(" ~ zones.key.argument ~ ")", zones.key.argument) %}
        LM = 2
        RETURN
{% endcall %}
{% endif %}
{% if guards %}
C     what has converged: the committed p_hist (STATEV(1) is passed in
C     as at the start of the increment)
      IF (STATEV(1) .GT. SBMFPU) THEN
        CALL SBMF_GUARD(6{{ " + KZ" if zones else "" }}, STATEV(1))
        RETURN
      END IF
      IF (STATEV(1) .GT. SBMFPM) CALL SBMF_GUARD(5{{ " + KZ" if zones else "" }}, STATEV(1))
C     an iterate above 100 H: a smaller increment, as long as this one
C     is above SBMFCF of the size at which that first happened (below,
C     the host's own limit would end the run: the increment is let
C     converge, and a converged pressure above 100 H stops it above)
      IF (P .GT. SBMFPU) THEN
        IF (SBMF_CUTS(KSTEP, KINC, DTIME) .GT. SBMFCF)
     &    PNEWDT = MIN(PNEWDT, SBMFCB)
      END IF
{% endif %}
      PH = STATEV(1)
      G1H = -1.0D0
{% if zones %}
C     the cache is this law's only if STATEV(4) says so
      IF (NSTATV .GE. 4) THEN
        IF (STATEV(4) .EQ. DBLE(IZ)) G1H = STATEV(2)
      END IF
{% else %}
      IF (NSTATV .GE. 2) G1H = STATEV(2)
{% endif %}
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
{% if flat and target.form.bulk_strain %}
      DEPS = 0.0D0
      SIGY = 0.0D0
      HMOD = 0.0D0
      IF (NPRED .GE. 1) THEN
        DEPS = MAX(PREDEF(2, 1), 0.0D0)
{% if flow %}
C       the flow stress and hardening modulus off the workpiece's flow
C       curve, at the middle of the increment's strain
        EM = MAX(PREDEF(1, 1) - 0.5D0*DEPS, 0.0D0)
        CALL SBMF_FLOW(EM, SIGY, HMOD)
{% endif %}
{% if guards %}
      ELSE
C       no strain passed: the flattened fraction is kept, not grown
        CALL SBMF_GUARD(9, 0.0D0)
{% endif %}
      END IF
      AF = 0.0D0
      IF (NSTATV .GE. 5) AF = MIN(MAX(STATEV(5), 0.0D0), 1.0D0)
{% if flat.limit %}
C     the two-state model (perfectly plastic)
      SF = 0.0D0
      IF (NSTATV .GE. 6) SF = MAX(STATEV(6), 0.0D0)
      CALL {{ "SBMF_ZTSHR(IZ, " if zones else "SBMF_TSHR(" }}P, PH, AF, SF, DEPS,
     &     SIGY, G1H, TLIM, DTAU, G1NEW, ANEW, SNEW)
C     HMOD: the one-state model's, set above and not read here
      IF (HMOD .LT. 0.0D0) CONTINUE
{% else %}
      CALL {{ "SBMF_ZFSHR(IZ, " if zones else "SBMF_FSHR(" }}P, PH, AF, DEPS, SIGY, HMOD, G1H, TLIM,
     &               DTAU, G1NEW, ANEW)
{% endif %}
{% else %}
      CALL {{ "SBMF_ZSHEAR(IZ, " if zones else "SBMF_SHEAR(" }}P, PH, G1H, TLIM, DTAU, G1NEW)
{% endif %}
      KFALL = MAX(TLIM, TINY(1.0D0))/(FSLIP*CHRLNGTH)
      XKT = {{ "SBMF_ZKT(IZ, " if zones else "SBMF_KT(" }}P, KFALL)
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
{% if zones %}
      IF (NSTATV .GE. 4) STATEV(4) = DBLE(IZ)
{% endif %}
{% if flat and target.form.bulk_strain %}
      IF (NSTATV .GE. 5) STATEV(5) = ANEW
{% if flat.limit %}
      IF (NSTATV .GE. 6) STATEV(6) = SNEW
{% endif %}
{% endif %}
      RETURN
      END
C
{% if flat and target.form.bulk_strain %}
C     The state variables FRIC needs (DEPVAR >= {{ flat_states }}: STATEV(1) = p_hist,
C     STATEV(5) = the flattened contact fraction{{ "," if flat.limit else ")." }}
{% if flat.limit %}
C     STATEV(6) = the flank slope).
{% endif %}
C     The CalculiX patch checks DEPVAR against it when ccx reads the
C     deck.
      INTEGER FUNCTION FRIC_DEPVAR()
      IMPLICIT NONE
      FRIC_DEPVAR = {{ flat_states }}
{% else %}
C     The state variables FRIC needs (DEPVAR >= 1: STATEV(1) = p_hist).
C     The CalculiX patch checks DEPVAR against it when ccx reads the
C     deck; Abaqus does not call it.
      INTEGER FUNCTION FRIC_DEPVAR()
      IMPLICIT NONE
      FRIC_DEPVAR = 1
{% endif %}
      RETURN
      END
C
C=======================================================================
C     The guards' view of the host's cut-backs: DTIME over the DTIME of
C     the first attempt of this increment (KSTEP, KINC) in which FRIC
C     saw an iterate above 100 H (1 in that attempt, 1/4 after one
C     cut-back to PNEWDT = 1/4, ...). Static storage of the process:
C     the increment's key and that DTIME, read and written with
C     sequentially consistent OpenMP atomics (DTIME before the key,
C     read after it). Every call of one attempt passes the same KSTEP,
C     KINC and DTIME, and attempts follow one another (the host's
C     threads join between iterations): threads that race in the
C     first attempt write the same values.
C=======================================================================
      DOUBLE PRECISION FUNCTION SBMF_CUTS(KSTEP, KINC, DTIME)
      IMPLICIT NONE
      INTEGER KSTEP, KINC
      DOUBLE PRECISION DTIME, D0
      INTEGER(8) KEY, K0
      INTEGER(8), SAVE :: SBMFCK = -1
      DOUBLE PRECISION, SAVE :: SBMFCD = 0.0D0
      KEY = INT(KSTEP, 8)*4294967296_8 + INT(KINC, 8)
!$OMP ATOMIC READ SEQ_CST
      K0 = SBMFCK
      IF (K0 .NE. KEY) THEN
!$OMP ATOMIC WRITE SEQ_CST
        SBMFCD = DTIME
!$OMP ATOMIC WRITE SEQ_CST
        SBMFCK = KEY
        SBMF_CUTS = 1.0D0
        RETURN
      END IF
!$OMP ATOMIC READ SEQ_CST
      D0 = SBMFCD
      SBMF_CUTS = 1.0D0
      IF (D0 .GT. 0.0D0) SBMF_CUTS = DTIME/D0
      RETURN
      END
C
{% include host.guards %}
{% include "core/sbmf_core.f" %}
{% if flow %}
{% include "core/sbmf_flow.f" %}
{% endif %}
