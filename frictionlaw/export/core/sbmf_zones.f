{#
  The zones of a zoned export (frictionlaw-export --zone NAME=FILE, issue 42), included by
  core/sbmf_core.f after the laws (core/sbmf_law.f, once per law with its prefix): the lookup
  of a name (SBMF_ZONE, or SBMF_ZONEN for a host that passes a number, LS-DYNA's NOSL), the
  dispatch to the law of a zone (SBMF_ZSHEAR, SBMF_ZKT) and the text of the unknown name
  (SBMF_ZMESSAGE). Context: zones (frictionlaw.export._zones.ZoneTable), laws (the CoreLaws,
  in the order of zones.laws), zone_text (the unknown name's message around the name).
#}
C=======================================================================
C     Zones: the law of the name the host passes. {{ zones.zones | length }} zone(s),
C     law i = zone i; {% if zones.default %}law {{ zones.default }}: the default, for every name no
C     zone gives{% else %}no default law: 0 for a name no zone gives
C     (the caller stops the run){% endif %}.
{% if zones.key.number %}
C     SBMF_ZONEN: the law of the number N ({{ zones.key.argument }}).
C=======================================================================
      INTEGER FUNCTION SBMF_ZONEN(N)
      IMPLICIT NONE
      INTEGER N
      SELECT CASE (N)
{% for law in zones.zones %}
      CASE ({{ law.key | int }})
        SBMF_ZONEN = {{ law.index }}
{% endfor %}
      CASE DEFAULT
        SBMF_ZONEN = {{ zones.default }}
      END SELECT
      RETURN
      END
C
{% else %}
C     SBMF_ZONE: the law of NAME ({{ zones.key.argument }}), compared trimmed
C     (leading and trailing blanks) and case-insensitive (ASCII).
C=======================================================================
      INTEGER FUNCTION SBMF_ZONE(NAME)
      IMPLICIT NONE
      CHARACTER*(*) NAME
      INTEGER I0, I1
      LOGICAL SBMF_ZEQ
      EXTERNAL SBMF_ZEQ
      SBMF_ZONE = {{ zones.default }}
      I1 = LEN_TRIM(NAME)
      I0 = 1
   10 IF (I0 .LT. I1) THEN
        IF (NAME(I0:I0) .EQ. ' ') THEN
          I0 = I0 + 1
          GOTO 10
        END IF
      END IF
      SELECT CASE (I1 - I0 + 1)
{% for n, group in zones.by_length() %}
      CASE ({{ n }})
{% for key, index in group %}
{% set parts = key | fchunks(44) %}
        IF (SBMF_ZEQ(NAME(I0:I1),
{% for c in parts %}
     &      {{ "// " if not loop.first else "" }}'{{ c }}'{{ ")) THEN" if loop.last else "" }}
{% endfor %}
          SBMF_ZONE = {{ index }}
          RETURN
        END IF
{% endfor %}
{% endfor %}
      END SELECT
      RETURN
      END
C
C     A = B for A of B's length, A's letters compared in upper case (B
C     is upper case).
      LOGICAL FUNCTION SBMF_ZEQ(A, B)
      IMPLICIT NONE
      CHARACTER*(*) A, B
      INTEGER I, C
      SBMF_ZEQ = .FALSE.
      DO I = 1, LEN(B)
        C = ICHAR(A(I:I))
        IF (C .GE. 97 .AND. C .LE. 122) C = C - 32
        IF (C .NE. ICHAR(B(I:I))) RETURN
      END DO
      SBMF_ZEQ = .TRUE.
      RETURN
      END
C
{% endif %}
C=======================================================================
C     Shear limit (SBMF_SHEAR) of law IZ, and its stick stiffness
C     (SBMF_KT); IZ outside 1..{{ laws | length }}: no friction (TAU = 0).
C=======================================================================
      SUBROUTINE SBMF_ZSHEAR(IZ, P, PH, G1H, TAU, DTAU, G1OUT)
      IMPLICIT NONE
      INTEGER IZ
      DOUBLE PRECISION P, PH, G1H, TAU, DTAU, G1OUT
      SELECT CASE (IZ)
{% for law in laws %}
      CASE ({{ loop.index }})
        CALL {{ law.prefix }}SHEAR(P, PH, G1H, TAU, DTAU, G1OUT)
{% endfor %}
      CASE DEFAULT
        TAU = 0.0D0
        DTAU = 0.0D0
        G1OUT = G1H
      END SELECT
      RETURN
      END
C
{% set two_state = laws | selectattr("flat") | selectattr("flat.limit") | list %}
{% if target.form.bulk_strain and laws | selectattr("flat") | list and not two_state %}
C=======================================================================
C     The flattening (issue 43) of law IZ: its SBMF_FSHR where the law
C     has a flattening block (the flattened fraction AF read through
C     that law's alpha1, grown by DEPS); a law without one runs its
C     SBMF_SHEAR and passes AF on unchanged (ANEW = AF), as the
C     runtime's ZonedLaw; IZ outside 1..{{ laws | length }}: no friction.
C=======================================================================
      SUBROUTINE SBMF_ZFSHR(IZ, P, PH, AF, DEPS, SIGY, HMOD, G1H, TAU,
     &                      DTAU, G1OUT, ANEW)
      IMPLICIT NONE
      INTEGER IZ
      DOUBLE PRECISION P, PH, AF, DEPS, SIGY, HMOD, G1H, TAU, DTAU
      DOUBLE PRECISION G1OUT, ANEW
      ANEW = AF
      SELECT CASE (IZ)
{% for law in laws %}
{% if law.flat %}
      CASE ({{ loop.index }})
        CALL {{ law.prefix }}FSHR(P, PH, AF, DEPS, SIGY, HMOD, G1H, TAU,
     &                  DTAU, G1OUT, ANEW)
{% endif %}
{% endfor %}
      CASE DEFAULT
C       a law without a flattening block (or no law): SBMF_ZSHEAR
        CALL SBMF_ZSHEAR(IZ, P, PH, G1H, TAU, DTAU, G1OUT)
      END SELECT
      RETURN
      END
C
{% endif %}
{% if target.form.bulk_strain and two_state %}
C=======================================================================
C     The flattening of law IZ where a zone has the two-state model:
C     that zone's law's TSHR (both states AF, SF read and grown); a
C     one-state zone its law's FSHR, perfectly plastic (as the runtime,
C     which takes no hardening modulus for a zoned law with a
C     two-state zone), the slope SF passed on (SNEW = SF); a zone
C     without a block SBMF_ZSHEAR, both states as they came.
C=======================================================================
      SUBROUTINE SBMF_ZTSHR(IZ, P, PH, AF, SF, DEPS, SIGY, G1H, TAU,
     &                      DTAU, G1OUT, ANEW, SNEW)
      IMPLICIT NONE
      INTEGER IZ
      DOUBLE PRECISION P, PH, AF, SF, DEPS, SIGY, G1H, TAU, DTAU
      DOUBLE PRECISION G1OUT, ANEW, SNEW
      ANEW = AF
      SNEW = SF
      SELECT CASE (IZ)
{% for law in laws %}
{% if law.flat and law.flat.limit %}
      CASE ({{ loop.index }})
        CALL {{ law.prefix }}TSHR(P, PH, AF, SF, DEPS, SIGY, G1H, TAU,
     &                  DTAU, G1OUT, ANEW, SNEW)
{% elif law.flat %}
      CASE ({{ loop.index }})
        CALL {{ law.prefix }}FSHR(P, PH, AF, DEPS, SIGY, 0.0D0, G1H, TAU,
     &                  DTAU, G1OUT, ANEW)
{% endif %}
{% endfor %}
      CASE DEFAULT
C       a law without a flattening block (or no law): SBMF_ZSHEAR
        CALL SBMF_ZSHEAR(IZ, P, PH, G1H, TAU, DTAU, G1OUT)
      END SELECT
      RETURN
      END
C
{% endif %}
      DOUBLE PRECISION FUNCTION SBMF_ZKT(IZ, P, KFALL)
      IMPLICIT NONE
      INTEGER IZ
      DOUBLE PRECISION P, KFALL
{% for law in laws %}
      DOUBLE PRECISION {{ law.prefix }}KT
      EXTERNAL {{ law.prefix }}KT
{% endfor %}
      SELECT CASE (IZ)
{% for law in laws %}
      CASE ({{ loop.index }})
        SBMF_ZKT = {{ law.prefix }}KT(P, KFALL)
{% endfor %}
      CASE DEFAULT
        SBMF_ZKT = KFALL
      END SELECT
      RETURN
      END
C
C=======================================================================
C     The message of a name no zone gives (and no default law covers):
C     MSG(1:NMSG), naming NAME (trimmed). MSG: 400 characters.
C=======================================================================
      SUBROUTINE SBMF_ZMESSAGE(NAME, MSG, NMSG)
      IMPLICIT NONE
      CHARACTER*(*) NAME, MSG
      INTEGER NMSG, N
      N = MAX(LEN_TRIM(NAME), 1)
      MSG = ''
{% for c in zone_text[0] | fchunks %}
     &    // '{{ c }}'
{% endfor %}
     &    // NAME(1:MIN(N, 80))
{% for c in zone_text[1] | fchunks %}
     &    // '{{ c }}'
{% endfor %}
      NMSG = LEN_TRIM(MSG)
      RETURN
      END
C
