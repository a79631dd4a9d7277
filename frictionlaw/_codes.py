"""Law codes and node status codes shared by the kernels and the Python layer (no numba here)."""

CODE_COULOMB = 0
CODE_TRESCA = 1
CODE_CAP = 2
CODE_SBMF = 3
CODE_SBMF_RELOAD = 4  # Eq. 25 alone, whatever p is (for alpha_reload)

# the reload form of codes 3 and 4 (coeffs[7], frictionlaw.reload_form)
FORM_PAPER = 0
FORM_TABULATED = 1
#: the tabulated form's x2 starts quadratically below p / p_hist = Q_START (finite d tau / dp)
Q_START = 0.01

# the first-loading form of codes 3 and 4 (the block after the reload table, frictionlaw.law)
FIRST_EQ24 = 0
FIRST_TABULATED = 1
#: coeffs index of the first slot after the header and s2, K (the reload table's z[0])
TABLE_START = 10

STATUS_OPEN = 0
STATUS_STICK = 1
STATUS_SLIP = 2
