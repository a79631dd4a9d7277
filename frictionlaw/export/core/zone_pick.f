{#
  How a zoned routine (frictionlaw-export --zone) chooses its law, one block every entry
  template calls where it has the host's name: IZ = the law of that name (core/sbmf_zones.f's
  lookup), then that law's guards (KZ, SBMFPU, SBMFPM: core/guard_decl.f). Where no law covers
  the name: SBMF_ZGUARD (the host's message and error exit, Host.guards) and the caller's own
  lines (its outputs without friction). Macro pick(lookup, name, write=""): lookup the Fortran
  expression of the law (SBMF_ZONE(CINAME)), name the CHARACTER argument the message names,
  write a statement that forms it first (LS-DYNA's number as text); the caller's block (call)
  is what the routine does for an unknown name. Context (imported with it): guards.
#}
{% macro pick(lookup, name, write="") %}
C     the zone's law, its 100 H and calibrated range
      IZ = {{ lookup }}
      IF (IZ .LT. 1) THEN
{% if guards %}
{% if write %}
        {{ write }}
{% endif %}
        CALL SBMF_ZGUARD({{ name }})
{% endif %}
{{ caller() }}      END IF
      KZ = 10*IZ
      SBMFPU = SBMFPZ(IZ)
      SBMFPM = SBMFMZ(IZ)
{% endmacro %}
