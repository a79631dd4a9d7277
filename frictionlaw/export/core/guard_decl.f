{#
  The guards' constants, declared in each entry routine that checks them (docs/fe_codes.md,
  "Guards"): SBMFU, the unit system the routine was exported for as the deck states it (1 SI,
  2 mm-t-s); SBMFPU, 100 H in the host's stress unit (a larger pressure stops the run);
  SBMFPM, the top of the calibrated range (the largest double when the parameter file records
  none). Context: guard (GuardSpec). A zoned routine (zones: its ZoneTable) has a law per zone
  with its own H and range: SBMFPU and SBMFPM are then the chosen law's (set from SBMFPZ(IZ),
  SBMFMZ(IZ) once the zone IZ is known), KZ = 10 IZ (the guards' message kinds of law IZ are
  KIND + KZ).
#}
{% if zones %}
      DOUBLE PRECISION SBMFU, SBMFPU, SBMFPM
      DOUBLE PRECISION SBMFPZ({{ laws | length }}), SBMFMZ({{ laws | length }})
      INTEGER IZ, KZ
      PARAMETER (SBMFU = {{ guard.code | double }})
      PARAMETER (SBMFPZ = (/
     &  {{ laws | map(attribute="guard.p_unit") | map("double") | join(",
     &  ") }} /))
      PARAMETER (SBMFMZ = (/
{% for law in laws %}
{% if law.guard.p_max is none %}
     &  HUGE(1.0D0){{ "," if not loop.last else " /))" }}
{% else %}
     &  {{ law.guard.p_max | double }}{{ "," if not loop.last else " /))" }}
{% endif %}
{% endfor %}
{% else %}
      DOUBLE PRECISION SBMFU, SBMFPU, SBMFPM
      PARAMETER (SBMFU = {{ guard.code | double }})
      PARAMETER (SBMFPU = {{ guard.p_unit | double }})
{% if guard.p_max is none %}
      PARAMETER (SBMFPM = HUGE(SBMFPU))
{% else %}
      PARAMETER (SBMFPM = {{ guard.p_max | double }})
{% endif %}
{% endif %}
