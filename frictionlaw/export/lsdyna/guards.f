{#
  SBMF_GUARD for LS-DYNA (Host.guards). LS-DYNA documents no error routine for user code:
  LSTC's user-routine file dyn21.f writes user messages to the terminal, d3hsp and messag
  units of its include file iounits.inc (IOTTY, IOHSP, IOMSG), as done here; the routine that
  calls SBMF_GUARD then refuses the law (no friction) where a guard fails (docs/fe_codes.md,
  "Guards").
#}
C=======================================================================
C     The guards' way to LS-DYNA: each kind of message is written once
C     per process (MPP: per rank) to the terminal, d3hsp and messag
C     (the units of LS-DYNA's iounits.inc, as LSTC's sample routines
C     in dyn21.f write theirs). LS-DYNA documents no error exit for
C     user routines: after an error (KIND 1-4) the caller applies no
C     friction (the law is refused); KIND 5 is a warning.
{% if zones %}
C     Zones: KIND + 10 i for law i.
{% endif %}
C=======================================================================
      SUBROUTINE SBMF_GUARD(KIND, XV)
      IMPLICIT NONE
      INCLUDE 'iounits.inc'
      INTEGER KIND, NMSG, IU, J
      DOUBLE PRECISION XV
      CHARACTER*400 MSG
      INTEGER SBMF_ONCE
      EXTERNAL SBMF_ONCE
      IF (SBMF_ONCE(KIND) .EQ. 0) RETURN
      CALL SBMF_MESSAGE(KIND, XV, MSG, NMSG)
      DO J = 1, 3
        IU = IOTTY
        IF (J .EQ. 2) IU = IOHSP
        IF (J .EQ. 3) IU = IOMSG
        IF (MOD(KIND, 10) .EQ. 5) THEN
          WRITE (IU, '(A, A)') ' *** Warning: ', MSG(1:NMSG)
        ELSE
          WRITE (IU, '(A, A)') ' *** Error: ', MSG(1:NMSG)
          WRITE (IU, '(A)') ' *** the SBMF friction law is refused '//
     &      'where this check fails: no friction there'
        END IF
      END DO
      RETURN
      END
C
{% if zones %}
C     An interface number no zone gives and no default law covers: the
C     message (once per process) names it; the caller applies no
C     friction on that interface.
      SUBROUTINE SBMF_ZGUARD(NAME)
      IMPLICIT NONE
      INCLUDE 'iounits.inc'
      CHARACTER*(*) NAME
      INTEGER NMSG, IU, J
      CHARACTER*400 MSG
      INTEGER SBMF_ONCE
      EXTERNAL SBMF_ONCE
      IF (SBMF_ONCE(7) .EQ. 0) RETURN
      CALL SBMF_ZMESSAGE(NAME, MSG, NMSG)
      DO J = 1, 3
        IU = IOTTY
        IF (J .EQ. 2) IU = IOHSP
        IF (J .EQ. 3) IU = IOMSG
        WRITE (IU, '(A, A)') ' *** Error: ', MSG(1:NMSG)
        WRITE (IU, '(A)') ' *** the SBMF friction law is refused '//
     &    'where this check fails: no friction there'
      END DO
      RETURN
      END
C
{% endif %}
