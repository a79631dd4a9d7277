{#
  The guards' common part, included by core/sbmf_core.f in every Fortran target
  (docs/fe_codes.md, "Guards"): SBMF_ONCE, the one static flag of the generated code (set
  with OpenMP atomics), and SBMF_MESSAGE, the text of each guard's message. Context:
  guard_text, the messages of GuardSpec.messages for the target's deck fields. How a message
  reaches the host is the host's guard template (Host.guards: SBMF_GUARD) or, for the
  host-neutral SBMF_FRICTION, its caller (the status IERR).
#}
C=======================================================================
C     1 for the first call with K in this process (or MPI rank), 0 for
C     every later one: the guards' once-per-process flags (K = the
C     message kind, 1..6). Static storage of the generated code (as
C     FRIC's SBMF_CUTS), read and set with OpenMP atomics (an exchange),
C     so that threads calling at once get one 1 between them when the
C     routine is compiled with the host's OpenMP flag (ifort -qopenmp,
C     gfortran -fopenmp); the atomics are hardware instructions and
C     hold for any threads, not only OpenMP's.
C=======================================================================
      INTEGER FUNCTION SBMF_ONCE(K)
      IMPLICIT NONE
      INTEGER K, N
      INTEGER, SAVE :: SBMFDN({{ guard_kinds }}) = 0
!$OMP ATOMIC READ
      N = SBMFDN(K)
      IF (N .EQ. 0) THEN
!$OMP ATOMIC CAPTURE
        N = SBMFDN(K)
        SBMFDN(K) = 1
!$OMP END ATOMIC
      END IF
      SBMF_ONCE = 1 - N
      RETURN
      END
C
C=======================================================================
C     The guards' messages: MSG(1:NMSG) for KIND and the value XV.
C     KIND 1: too few state variables (XV: their number); 2: the deck
C     states no unit system; 3: it states another one (XV: the value
C     stated); 4: a pressure above 100 H (XV: p); 5: a pressure beyond
C     the calibrated range (XV: p; a warning, written once per
C     process); 6: a committed p_hist above 100 H (FRIC; XV: p_hist);
C     10: more properties than the unit system's (FRIC; XV: their
C     number). Errors (all but 5) stop the analysis. MSG: 400
C     characters.
C=======================================================================
      SUBROUTINE SBMF_MESSAGE(KIND, XV, MSG, NMSG)
      IMPLICIT NONE
      INTEGER KIND, NMSG
      DOUBLE PRECISION XV
      CHARACTER*(*) MSG
      CHARACTER*24 V
      IF (ABS(XV) .LT. 1.0D6 .AND. XV .EQ. DBLE(NINT(XV))) THEN
        WRITE (V, '(I0)') NINT(XV)
      ELSE
        WRITE (V, '(ES12.5)') XV
      END IF
      V = ADJUSTL(V)
      SELECT CASE (KIND)
{% for kind, (before, after) in guard_text.items() %}
      CASE ({{ kind }})
        MSG = ''
{% for c in before | fchunks %}
     &    // '{{ c }}'
{% endfor %}
{% if after is not none %}
     &    // V(1:LEN_TRIM(V))
{% for c in after | fchunks %}
     &    // '{{ c }}'
{% endfor %}
{% endif %}
{% endfor %}
      CASE DEFAULT
        MSG = 'SBMF friction: no message of this kind'
      END SELECT
      NMSG = LEN_TRIM(MSG)
      RETURN
      END
C
