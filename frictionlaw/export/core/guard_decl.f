{#
  The guards' constants, declared in each entry routine that checks them (docs/fe_codes.md,
  "Guards"): SBMFU, the unit system the routine was exported for as the deck states it (1 SI,
  2 mm-t-s); SBMFPU, 100 H in the host's stress unit (a larger pressure stops the run);
  SBMFPM, the top of the calibrated range (the largest double when the parameter file records
  none). Context: guard (GuardSpec).
#}
      DOUBLE PRECISION SBMFU, SBMFPU, SBMFPM
      PARAMETER (SBMFU = {{ guard.code | double }})
      PARAMETER (SBMFPU = {{ guard.p_unit | double }})
{% if guard.p_max is none %}
      PARAMETER (SBMFPM = HUGE(SBMFPU))
{% else %}
      PARAMETER (SBMFPM = {{ guard.p_max | double }})
{% endif %}
