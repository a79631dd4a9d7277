C=======================================================================
C     LS-DYNA SMP user friction usrfrc (argument list and conventions
C     of the sample usrfrc in LSTC's user file dyn21.f). Called once
C     per cycle with the NIISV5 active slave nodes IISV5(:). All host
C     arguments have the host's default REAL/INTEGER (compile with the
C     host's flags: SP as is, DP with ifort -r8 -i8 or gfortran
C     -fdefault-real-8 -fdefault-double-8 -fdefault-integer-8); the
C     law is computed in double precision.
C     p = -FNI/AREAS (FNI < 0 in compression). Trial friction force:
C     tangential part of FDAT(3:5) (old friction force) + STFK SFACN3
C     (DX, DY, DZ) (k_t = STFK SFACN3/AREAS unless the export baked in
C     a calibrated k_t); return map of the law on tractions (force /
C     AREAS), as frictionlaw.traction_update_force; the new force is
C     stored in FDAT(3:5) and added to FXIS, FYIS, FZIS.
C     UFHIST(1, ILBSV(II)) = p_hist (NHV >= 1; stored rounded down to
C     the host REAL), UFHIST(2, .) = cache -ln alpha1(p_hist) (NHV >= 2,
C     used in double-precision hosts only), UFHIST(3, .) = status of
C     the last cycle 0 open 1 stick 2 slip (NHV >= 3).
C     FNI >= 0 or AREAS <= 0: open (no friction, FDAT(3:5) = 0,
C     history unchanged). The Coulomb coefficients FRIC1..4, FRC and
C     the thermal data are not used.
C     UA(1), the first user parameter of *USER_INTERFACE_FRICTION
C     (NINPUT >= 1), states the deck's unit system: 1 SI (Pa, m), 2
C     mm-t-s (MPa, mm). Guards (docs/fe_codes.md): NHV >= 1, UA(1) =
C     the unit system this routine was exported for, else no friction
C     at any node; p > 100 H: no friction at that node; each with one
C     message per process (terminal, d3hsp, messag: iounits.inc).
C     p beyond the calibrated range: one warning per process.
{% if flat %}
C     Flattening under bulk strain (the file's flattening block): the
C     slave node's element plastic strain UFEPS(1, ILBSV(II)) (NEPS >=
C     1), its increment since the last cycle in contact, UFHIST(5, .)
C     = the flattened contact fraction, UFHIST(6, .) = the plastic
C     strain and UFHIST(7, .) = MOD(cycle, 2**20) + 1 of the last call
C     in contact{% if flat.limit %}, UFHIST(8, .) = the asperities' flank slope (the
C     two-state model){% endif %} (NHV >= {{ flat_states }}). Without them the law runs
C     without flattening and says so once (a warning).
{% endif %}
{% if zones %}
C     Zones: the law of the interface number NOSL ({{ zones.laws | length }} laws);
C     {% if zones.default %}an interface no zone gives runs the default law{% else %}an interface no zone gives: no friction on it and one
C     message (no default law){% endif %}. UFHIST(4, .)
C     = the law that wrote the cache (NHV >= 4); p_hist carries over.
{% endif %}
{% from "core/zone_pick.f" import pick with context %}
C=======================================================================
      SUBROUTINE USRFRC(NOSL,TIME,NCYCLE,DT2,INSV,AREAS,XS,YS,ZS,
     & LSV,IX1,IX2,IX3,IX4,AREAM,XX1,XX2,XX3,STFN,STF,FNI,
     & DX,DY,DZ,FDT2,NINPUT,UA,SIDE,IISV5,NIISV5,RN1,RN2,RN3,FRIC1,
     & FRIC2,FRIC3,FRIC4,BIGNUM,FDAT,ISEG,FXIS,FYIS,FZIS,SS,TT,
     & ILBSV,STFK,FRC,NUMNP,NPC,PLD,LCFST,LCFDT,TEMP,TEMP_BOT,
     & TEMP_TOP,ISURFACE,NHV,UFHIST,NEPS,UFEPS,SFACN3)
      IMPLICIT NONE
      INTEGER NOSL, NCYCLE, NINPUT, NIISV5, NUMNP, NHV, NEPS
      INTEGER INSV(*), LSV(*), IX1(*), IX2(*), IX3(*), IX4(*)
      INTEGER IISV5(*), ISEG(*), ILBSV(*), NPC(*), LCFST(*), LCFDT(*)
      INTEGER ISURFACE(*)
      REAL TIME, DT2, FDT2, FRIC1, FRIC2, FRIC3, FRIC4, BIGNUM, SFACN3
      REAL AREAS(*), XS(*), YS(*), ZS(*), AREAM(*), XX1(*), XX2(*)
      REAL XX3(*), STFN(*), STF(*), FNI(*), DX(*), DY(*), DZ(*), UA(*)
      REAL RN1(*), RN2(*), RN3(*), FDAT(5,*), FXIS(*), FYIS(*)
      REAL FZIS(*), SS(*), TT(*), STFK(*), FRC(2,*), PLD(2,*), TEMP(*)
      REAL TEMP_BOT(*), TEMP_TOP(*), UFHIST(NHV,*), UFEPS(NEPS,*)
      CHARACTER*(*) SIDE
C
      INTEGER KK, II, IH, A, ISTAT
      DOUBLE PRECISION P, PH, PHNEW, G1H, G1NEW, TLIM, DTAU, AR, FN
      DOUBLE PRECISION RN(3), FO(3), D(3), Q, KT, HD, HR, F
      DOUBLE PRECISION TOLD(3), TNEW(3), DTDDU(3,3), DTDP(3)
      REAL RPH
      LOGICAL USECAC, REFUSE
{% if flat %}
      DOUBLE PRECISION AF, ANEW, DEPS, SIGY, HMOD
{% if flat.limit %}
      DOUBLE PRECISION SF, SNEW
{% endif %}
{% if flow %}
      DOUBLE PRECISION EM
{% endif %}
      REAL RA
      LOGICAL FLATOK
{% endif %}
{% if zones %}
      CHARACTER*12 ZNAME
      DOUBLE PRECISION SBMF_ZKT
      INTEGER SBMF_ZONEN
      EXTERNAL SBMF_ZKT, SBMF_ZONEN
{% else %}
      DOUBLE PRECISION SBMF_KT
      EXTERNAL SBMF_KT
{% endif %}
{% include "core/guard_decl.f" %}
C     largest double and largest host REAL
      HD = HUGE(HD)
      HR = DBLE(HUGE(RPH))
C     the cache is exact only where the host REAL is a double
      USECAC = (KIND(RPH) .EQ. KIND(HD)) .AND. (NHV .GE. 2)
      REFUSE = .FALSE.
{% if guards %}
C     guards: the deck's history variables and unit system; a failed
C     one refuses the law (no friction at any node, history unchanged)
      IF (NHV .LT. 1) THEN
        CALL SBMF_GUARD(1, DBLE(NHV))
        REFUSE = .TRUE.
      ELSE IF (NINPUT .LT. 1) THEN
        CALL SBMF_GUARD(2, 0.0D0)
        REFUSE = .TRUE.
      ELSE IF (DBLE(UA(1)) .NE. SBMFU) THEN
        CALL SBMF_GUARD(3, DBLE(UA(1)))
        REFUSE = .TRUE.
      END IF
{% endif %}
{% if zones %}
{% call pick("SBMF_ZONEN(NOSL)", "ZNAME", "WRITE (ZNAME, '(I0)') NOSL") %}
        REFUSE = .TRUE.
        IZ = 1
{% endcall %}
      USECAC = USECAC .AND. (NHV .GE. 4)
{% endif %}
{% if flat %}
C     the flattening needs the element plastic strain and {{ flat_states - 4 }} more
C     history variables: without them the law without it, said once
      FLATOK = NEPS .GE. 1 .AND. NHV .GE. {{ flat_states }}
{% if guards %}
      IF (.NOT. (FLATOK .OR. REFUSE)) CALL SBMF_GUARD(9, 0.0D0)
{% endif %}
{% endif %}
      DO KK = 1, NIISV5
        II = IISV5(KK)
        IH = ILBSV(II)
        ISEG(II) = LSV(II)
        FDAT(1, II) = SS(II)
        FDAT(2, II) = TT(II)
        AR = DBLE(AREAS(II))
        FN = -DBLE(FNI(II))
        IF (REFUSE .OR. .NOT. (FN .GT. 0.0D0 .AND. AR .GT. 0.0D0)) THEN
          DO A = 3, 5
            FDAT(A, II) = 0.0
          END DO
          IF (NHV .GE. 3 .AND. .NOT. REFUSE) UFHIST(3, IH) = 0.0
          CYCLE
        END IF
        P = MIN(FN/AR, HD)
{% if guards %}
        IF (P .GT. SBMFPU) THEN
C         the deck's units are not the routine's: no friction here
          CALL SBMF_GUARD(4{{ " + KZ" if zones else "" }}, P)
          DO A = 3, 5
            FDAT(A, II) = 0.0
          END DO
          CYCLE
        END IF
        IF (P .GT. SBMFPM) CALL SBMF_GUARD(5{{ " + KZ" if zones else "" }}, P)
{% endif %}
        PH = 0.0D0
        IF (NHV .GE. 1) PH = MAX(DBLE(UFHIST(1, IH)), 0.0D0)
        G1H = -1.0D0
{% if zones %}
C       the cache is this law's only if UFHIST(4, .) says so
        IF (USECAC) THEN
          IF (DBLE(UFHIST(4, IH)) .EQ. DBLE(IZ))
     &      G1H = DBLE(UFHIST(2, IH))
        END IF
{% else %}
        IF (USECAC) G1H = DBLE(UFHIST(2, IH))
{% endif %}
        RN(1) = DBLE(RN1(II))
        RN(2) = DBLE(RN2(II))
        RN(3) = DBLE(RN3(II))
        D(1) = DBLE(DX(II))
        D(2) = DBLE(DY(II))
        D(3) = DBLE(DZ(II))
        DO A = 1, 3
          FO(A) = DBLE(FDAT(2 + A, II))
        END DO
C       tangential parts: the normal components projected out
        Q = FO(1)*RN(1) + FO(2)*RN(2) + FO(3)*RN(3)
        DO A = 1, 3
          FO(A) = FO(A) - Q*RN(A)
        END DO
        Q = D(1)*RN(1) + D(2)*RN(2) + D(3)*RN(3)
        DO A = 1, 3
          D(A) = D(A) - Q*RN(A)
        END DO
C       tractions: t_old = F_old/A, k_t = STFK SFACN3/A (kept finite)
        KT = MAX(MIN((DBLE(STFK(II))*DBLE(SFACN3))/AR, HD), 0.0D0)
C       a calibrated k_t (table or --k-t) replaces the penalty's
{% if zones %}
        KT = SBMF_ZKT(IZ, P, KT)
{% else %}
        KT = SBMF_KT(P, KT)
{% endif %}
        DO A = 1, 3
          TOLD(A) = MAX(MIN(FO(A)/AR, HD), -HD)
        END DO
{% if flat %}
        IF (FLATOK) THEN
          AF = MIN(MAX(DBLE(UFHIST(5, IH)), 0.0D0), 1.0D0)
C         the strain since the last cycle, if the point was in contact
C         then (else it starts counting now)
          DEPS = 0.0D0
          IF (NINT(UFHIST(7, IH)) .EQ. MOD(NCYCLE - 1, 1048576) + 1)
     &      DEPS = MAX(DBLE(UFEPS(1, IH)) - DBLE(UFHIST(6, IH)), 0.0D0)
{% if flow %}
C         the flow stress and hardening modulus off the workpiece's
C         flow curve, at the middle of the cycle's strain
          EM = MAX(DBLE(UFEPS(1, IH)) - 0.5D0*DEPS, 0.0D0)
          CALL SBMF_FLOW(EM, SIGY, HMOD)
{% else %}
C         no flow curve: the file's sigma_y, perfectly plastic
          SIGY = 0.0D0
          HMOD = 0.0D0
{% endif %}
{% if flat.limit %}
C         the two-state model (perfectly plastic)
          SF = DBLE(UFHIST(8, IH))
          CALL {{ "SBMF_ZTSHR(IZ, " if zones else "SBMF_TSHR(" }}P, PH, AF, SF, DEPS,
     &         SIGY, G1H, TLIM, DTAU, G1NEW, ANEW, SNEW)
C         HMOD: the one-state model's, set above and not read here
          IF (HMOD .LT. 0.0D0) CONTINUE
{% else %}
          CALL {{ "SBMF_ZFSHR(IZ, " if zones else "SBMF_FSHR(" }}P, PH, AF, DEPS, SIGY, HMOD, G1H,
     &                   TLIM, DTAU, G1NEW, ANEW)
{% endif %}
        ELSE
          CALL {{ "SBMF_ZSHEAR(IZ, " if zones else "SBMF_SHEAR(" }}P, PH, G1H, TLIM, DTAU, G1NEW)
        END IF
{% elif zones %}
        CALL SBMF_ZSHEAR(IZ, P, PH, G1H, TLIM, DTAU, G1NEW)
{% else %}
        CALL SBMF_SHEAR(P, PH, G1H, TLIM, DTAU, G1NEW)
{% endif %}
        CALL SBMF_RMAP(3, TLIM, DTAU, D, TOLD, KT, TNEW, DTDDU, DTDP,
     &                 ISTAT)
        DO A = 1, 3
          F = MAX(MIN(TNEW(A)*AR, HR), -HR)
          FDAT(2 + A, II) = REAL(F)
        END DO
        FXIS(II) = FXIS(II) + FDAT(3, II)
        FYIS(II) = FYIS(II) + FDAT(4, II)
        FZIS(II) = FZIS(II) + FDAT(5, II)
        PHNEW = MAX(PH, P)
        IF (NHV .GE. 1) THEN
C         stored rounded down: a constant pressure stays on Eq. 24
          RPH = REAL(MIN(PHNEW, HR))
          IF (DBLE(RPH) .GT. PHNEW) RPH = NEAREST(RPH, -1.0)
          UFHIST(1, IH) = RPH
        END IF
        IF (USECAC) THEN
          UFHIST(2, IH) = REAL(G1NEW)
{% if zones %}
          UFHIST(4, IH) = REAL(IZ)
{% endif %}
        ELSE IF (NHV .GE. 2) THEN
          UFHIST(2, IH) = 0.0
        END IF
        IF (NHV .GE. 3) UFHIST(3, IH) = REAL(ISTAT)
{% if flat %}
        IF (FLATOK) THEN
C         stored rounded to nearest: never below the stored fraction
C         (ANEW >= AF, which REAL holds), and unbiased over many
C         cycles (rounded down, as p_hist, it lost 0.5 ulp a cycle)
          RA = REAL(ANEW)
          UFHIST(5, IH) = RA
          UFHIST(6, IH) = UFEPS(1, IH)
          UFHIST(7, IH) = REAL(MOD(NCYCLE, 1048576) + 1)
{% if flat.limit %}
          UFHIST(8, IH) = REAL(SNEW)
{% endif %}
        END IF
{% endif %}
      END DO
      RETURN
      END
C
{% include host.guards %}
{% include "core/sbmf_core.f" %}
{% if flow %}
{% include "core/sbmf_flow.f" %}
{% endif %}
