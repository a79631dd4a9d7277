{#
  SBMF_GUARD for hosts with Abaqus' utility routines (Host.guards): Abaqus/Standard
  (STDB_ABQERR, XIT), Abaqus/Explicit (XPLB_ABQERR, XPLB_EXIT) and the patched CalculiX, which
  provides STDB_ABQERR and XIT. The names come from the Host record (message_routine,
  exit_routine), the text from SBMF_MESSAGE (core/sbmf_guards.f). A zoned routine (zones) adds
  SBMF_ZGUARD: the name no zone gives, an error (SBMF_ZMESSAGE, core/sbmf_zones.f).
#}
C=======================================================================
C     The guards' way to {{ host.name }}: {{ host.message_routine }}
C     writes the message; an error (every KIND but 5) is written with
C     LOP = -3 and ends the analysis ({{ host.exit_routine }} after it,
C     should the host return); the warning (KIND 5) with LOP = -1,
C     once per process.
{% if zones %}
C     Zones: KIND + 10 i for law i.
{% endif %}
C=======================================================================
      SUBROUTINE SBMF_GUARD(KIND, XV)
      IMPLICIT NONE
      INTEGER KIND, NMSG, INTV(1)
      DOUBLE PRECISION XV, REALV(1)
      CHARACTER*8 CHARV(1)
      CHARACTER*400 MSG
      INTEGER SBMF_ONCE
      EXTERNAL SBMF_ONCE
      INTV(1) = KIND
      REALV(1) = XV
      CHARV(1) = 'SBMF'
      IF (MOD(KIND, 10) .EQ. 5) THEN
        IF (SBMF_ONCE(KIND) .EQ. 0) RETURN
        CALL SBMF_MESSAGE(KIND, XV, MSG, NMSG)
        CALL {{ host.message_routine }}(-1, MSG(1:NMSG), INTV, REALV,
     &                   CHARV)
        RETURN
      END IF
      CALL SBMF_MESSAGE(KIND, XV, MSG, NMSG)
      CALL {{ host.message_routine }}(-3, MSG(1:NMSG), INTV, REALV, CHARV)
      CALL {{ host.exit_routine }}
      RETURN
      END
C
{% if zones %}
C     A name no zone gives and no default law covers: an error that
C     names it ({{ host.message_routine }}, LOP = -3, then {{ host.exit_routine }}).
      SUBROUTINE SBMF_ZGUARD(NAME)
      IMPLICIT NONE
      CHARACTER*(*) NAME
      INTEGER NMSG, INTV(1)
      DOUBLE PRECISION REALV(1)
      CHARACTER*8 CHARV(1)
      CHARACTER*400 MSG
      INTV(1) = 7
      REALV(1) = 0.0D0
      CHARV(1) = 'SBMF'
      CALL SBMF_ZMESSAGE(NAME, MSG, NMSG)
      CALL {{ host.message_routine }}(-3, MSG(1:NMSG), INTV, REALV, CHARV)
      CALL {{ host.exit_routine }}
      RETURN
      END
C
{% endif %}
