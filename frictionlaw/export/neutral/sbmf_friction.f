C=======================================================================
C     Host-neutral entry point, interface version 2, to be called from
C     the host's friction template (see the README): one contact point
C     per call.
C     In:  IVERS, the interface version the caller was written for: 2
C          (another value: IERR = -8, nothing else is touched),
C          ZONE, the zone's name (CHARACTER*(*), compared trimmed and
C          case-insensitive; {% if zones %}this routine has {{ zones.zones | length }} zone(s){% if zones.default %} and
C          a default law for every other name{% else %} and no default
C          law: another name returns IERR = -7{% endif %}{% else %}a one-law routine runs
C          its law for every name{% endif %}),
C          ND (1 or 2 tangential directions), P (contact pressure),
C          DU(ND) (slip increment since the last converged state),
C          TOLD(ND) (traction of the last converged state),
C          KHOST (the host's tangential penalty, used only when the
C          parameter file has no calibrated k_t and no --k-t was given),
C          IUNIT (the unit system the deck states: 1 SI (Pa, m),
C          2 mm-t-s (MPa, mm); 0: the deck states none),
C          DEPS (the point's bulk plastic strain increment of the
C          increment, >= 0) and SIGY (its current flow stress, host
C          stress unit; <= 0: the parameter file's sigma_y): the
C          flattening of the asperities under bulk strain (issue 43),
{% if flat %}
C          read by this law's flattening block (the trial fraction
C          goes to STATE(5)),
{% else %}
C          read where the law has a flattening block (this one has
C          none: accepted and not used),
{% endif %}
C          NSTATE (the caller's state count: SBMF_NSTATE() gives every
C          slot, at least 1),
C          STATE(NSTATE): the committed state (as at the start of the
C          increment): 1 p_hist, 2 cache -ln alpha1(p_hist) (<= 0:
C          recompute), 3 status of the last call, 4 the law (zone
C          number) that wrote the cache, 5 the flattened contact
{% if flat and flat.limit %}
C          fraction alpha_f (0: never flattened; read and written),
C          6 not read (the one-state model's hardening modulus: the
C          two-state model of this law's block is perfectly plastic),
C          7 the asperities' flank slope s_f (0: never flattened, the
C          block's slope; read and written).
{% elif flat %}
C          fraction alpha_f (0: never flattened; read and written),
C          6 an input the caller sets before each call, read and
C          never written: the bulk's hardening modulus d sigma_y /
C          d eps_eq at the point (host stress unit; <= 0 or NSTATE < 6:
C          perfectly plastic), which limits the flattening's lattice
C          and its sinking (Eqs. F2c, F2d).
{% else %}
C          fraction alpha_f (0: never flattened; kept as passed: this
C          law has no flattening block), 6 the bulk's hardening
C          modulus (an input of a law with a flattening block; not
C          read here).
{% endif %}
C     Out: STATE: the trial state, which the caller stores only when
C          the host accepts (converges) the increment; TNEW(ND),
C          DTDDU(ND,ND), DTDP(ND), ISTAT (0 open, 1 stick, 2 slip).
C          IERR, the guards' status, which the caller must check:
C          0 fine; < 0 an error, the caller must stop the analysis:
C          -2 IUNIT = 0 (no unit system stated), -3 IUNIT is not the
C          unit system this routine was exported for, -6 p_hist > 100 H
C          (a converged pressure: the deck's units are not the
C          routine's), -4 P > 100 H (the same for an explicit caller;
C          an implicit caller, whose P may be a Newton iterate, should
C          take a smaller substep instead), -7 a ZONE no law covers,
C          -8 another IVERS; 5 a warning: the first P beyond the
C          calibrated range in this process (once per process); 9 a
C          warning: the law has a flattening block and NSTATE < {{ 7 if flat and flat.limit else 5 }}
C          leaves no slot for its state, so it runs without
C          flattening (once per process).
{% if zones %}
C          In this zoned routine the codes of -4, 5 and -6 carry the
C          zone's law i as -(4 + 10 i), 5 + 10 i, -(6 + 10 i):
C          MOD(ABS(IERR), 10) is the kind.
{% endif %}
C          The outputs are the law's in every case but -7 and -8.
C          CALL SBMF_MESSAGE(ABS(IERR), XV, MSG, NMSG) gives the text
C          (XV: DBLE(IUNIT) for -3, P for -4 and 5, p_hist for -6,
C          DBLE(IVERS) for -8; MSG CHARACTER*400), for -7
C          CALL SBMF_ZMESSAGE(ZONE, MSG, NMSG).
C=======================================================================
      SUBROUTINE SBMF_FRICTION_V(IVERS, ZONE, ND, P, DU, TOLD, KHOST,
     &                           IUNIT, DEPS, SIGY, NSTATE, STATE,
     &                           TNEW, DTDDU, DTDP, ISTAT, IERR)
      IMPLICIT NONE
      INTEGER IVERS, ND, IUNIT, NSTATE, ISTAT, IERR
      CHARACTER*(*) ZONE
      DOUBLE PRECISION P, DU(ND), TOLD(ND), KHOST, DEPS, SIGY
      DOUBLE PRECISION STATE(NSTATE), TNEW(ND), DTDDU(ND, ND), DTDP(ND)
      DOUBLE PRECISION PH, G1H, G1NEW, TLIM, DTAU, XKT
{% if flat and flat.limit %}
      DOUBLE PRECISION AF, ANEW, SF, SNEW
{% elif flat %}
      DOUBLE PRECISION AF, ANEW, HMOD
{% endif %}
      INTEGER SBMF_ONCE
{% if zones %}
      DOUBLE PRECISION SBMF_ZKT
      INTEGER SBMF_ZONE
      EXTERNAL SBMF_ZKT, SBMF_ONCE, SBMF_ZONE
{% else %}
      DOUBLE PRECISION SBMF_KT
      EXTERNAL SBMF_KT, SBMF_ONCE
      INTEGER IZ
      PARAMETER (IZ = 1)
{% endif %}
{% include "core/guard_decl.f" %}
      IERR = 0
      IF (IVERS .NE. 2) THEN
        IERR = -8
        RETURN
      END IF
{% if not flat %}
C     DEPS, SIGY: read by a law with a flattening block (none here)
      IF (DEPS .LT. 0.0D0 .AND. SIGY .LT. 0.0D0) CONTINUE
{% endif %}
{% if zones %}
      IZ = SBMF_ZONE(ZONE)
      IF (IZ .LT. 1) THEN
        IERR = -7
        CALL SBMF_OPEN(ND, TNEW, DTDDU, DTDP, ISTAT)
        RETURN
      END IF
      KZ = 10*IZ
      SBMFPU = SBMFPZ(IZ)
      SBMFPM = SBMFMZ(IZ)
{% else %}
      IF (ZONE .EQ. '') CONTINUE
{% endif %}
      PH = STATE(1)
      G1H = -1.0D0
      IF (NSTATE .GE. 4) THEN
C       the cache is this law's only if STATE(4) says so
        IF (STATE(4) .EQ. DBLE(IZ)) G1H = STATE(2)
{% if not zones %}
      ELSE IF (NSTATE .GE. 2) THEN
C       no record of the law: a one-law routine's own cache
        G1H = STATE(2)
{% endif %}
      END IF
{% if guards %}
C     guards: the stated unit system, the pressure (the caller reports)
      IF (IUNIT .EQ. 0) THEN
        IERR = -2
      ELSE IF (DBLE(IUNIT) .NE. SBMFU) THEN
        IERR = -3
      ELSE IF (PH .GT. SBMFPU) THEN
        IERR = -6{{ " - KZ" if zones else "" }}
      ELSE IF (P .GT. SBMFPU) THEN
        IERR = -4{{ " - KZ" if zones else "" }}
      ELSE IF (P .GT. SBMFPM) THEN
        IF (SBMF_ONCE(5{{ " + KZ" if zones else "" }}) .EQ. 1) IERR = 5{{ " + KZ" if zones else "" }}
      END IF
{% endif %}
      IF (.NOT. (P .GT. 0.0D0)) THEN
        CALL SBMF_OPEN(ND, TNEW, DTDDU, DTDP, ISTAT)
        IF (NSTATE .GE. 3) STATE(3) = 0.0D0
        RETURN
      END IF
{% if flat and flat.limit %}
      IF (NSTATE .GE. 7) THEN
C       the two-state model: STATE(5) the fraction, STATE(7) the slope
        AF = STATE(5)
        SF = STATE(7)
        CALL {{ "SBMF_ZTSHR(IZ, " if zones else "SBMF_TSHR(" }}P, PH, AF, SF, DEPS,
     &       SIGY, G1H, TLIM, DTAU, G1NEW, ANEW, SNEW)
        STATE(5) = ANEW
        STATE(7) = SNEW
      ELSE
C       no slots for the two states: the law without flattening
        IF (DEPS .GT. 0.0D0 .AND. IERR .EQ. 0) THEN
          IF (SBMF_ONCE(9) .EQ. 1) IERR = 9
        END IF
        CALL {{ "SBMF_ZSHEAR(IZ, " if zones else "SBMF_SHEAR(" }}P, PH, G1H, TLIM, DTAU, G1NEW)
      END IF
{% elif flat %}
      IF (NSTATE .GE. 5) THEN
        AF = STATE(5)
        HMOD = 0.0D0
        IF (NSTATE .GE. 6) HMOD = MAX(STATE(6), 0.0D0)
        CALL {{ "SBMF_ZFSHR(IZ, " if zones else "SBMF_FSHR(" }}P, PH, AF, DEPS, SIGY, HMOD, G1H, TLIM,
     &                 DTAU, G1NEW, ANEW)
        STATE(5) = ANEW
      ELSE
C       no slot for the flattened fraction: the law without flattening
        IF (DEPS .GT. 0.0D0 .AND. IERR .EQ. 0) THEN
          IF (SBMF_ONCE(9) .EQ. 1) IERR = 9
        END IF
        CALL {{ "SBMF_ZSHEAR(IZ, " if zones else "SBMF_SHEAR(" }}P, PH, G1H, TLIM, DTAU, G1NEW)
      END IF
{% else %}
      CALL {{ "SBMF_ZSHEAR(IZ, " if zones else "SBMF_SHEAR(" }}P, PH, G1H, TLIM, DTAU, G1NEW)
{% endif %}
      XKT = {{ "SBMF_ZKT(IZ, " if zones else "SBMF_KT(" }}P, KHOST)
      CALL SBMF_RMAP(ND, TLIM, DTAU, DU, TOLD, XKT, TNEW, DTDDU, DTDP,
     &               ISTAT)
      STATE(1) = MAX(PH, P)
      IF (NSTATE .GE. 2) STATE(2) = G1NEW
      IF (NSTATE .GE. 3) STATE(3) = DBLE(ISTAT)
      IF (NSTATE .GE. 4) STATE(4) = DBLE(IZ)
      RETURN
      END
C
C     No friction: zero traction and tangents, status 0 (open).
      SUBROUTINE SBMF_OPEN(ND, TNEW, DTDDU, DTDP, ISTAT)
      IMPLICIT NONE
      INTEGER ND, ISTAT, A, B
      DOUBLE PRECISION TNEW(ND), DTDDU(ND, ND), DTDP(ND)
      DO A = 1, ND
        TNEW(A) = 0.0D0
        DTDP(A) = 0.0D0
        DO B = 1, ND
          DTDDU(A, B) = 0.0D0
        END DO
      END DO
      ISTAT = 0
      RETURN
      END
C
C     The state count that gives every slot of SBMF_FRICTION_V's STATE
C     (p_hist, its cache, the status, the law of the cache, the
C     flattening state, the bulk's hardening modulus): allocate this
C     many per contact point.
      INTEGER FUNCTION SBMF_NSTATE()
      IMPLICIT NONE
      SBMF_NSTATE = {{ 7 if flat and flat.limit else 6 }}
      RETURN
      END
C
{% include "neutral/sbmf_friction_v1.f" %}
{% if not zones %}
C     The message of status -7 (a zoned routine's name no law covers):
C     this routine has one law for every name and never returns -7;
C     SBMF_ZMESSAGE is here so that a caller written for zoned routines
C     links against every routine.
      SUBROUTINE SBMF_ZMESSAGE(NAME, MSG, NMSG)
      IMPLICIT NONE
      CHARACTER*(*) NAME, MSG
      INTEGER NMSG
      MSG = 'SBMF friction: this routine runs one law for every zone '
     &    // 'name (' // NAME(1:MIN(LEN_TRIM(NAME), 80)) // ' included)'
      NMSG = LEN_TRIM(MSG)
      RETURN
      END
C
{% endif %}
{% include "core/sbmf_core.f" %}
