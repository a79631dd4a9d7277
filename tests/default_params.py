"""The default calibration's parameters (halfspace-calib's built-in scene), as test inputs.

Regenerated for issue 26: the default sweep reaches 760 MPa (0.95 H) and the fit of Eq. 24 is
bounded by alpha1 >= p / H up to 0.99 H (``calibrate(Scene()).params``, 128^2, tol 1e-8).
"""

DEFAULT = dict(
    m=0.5,
    sigma_y=285714285.71428573,
    H=800000000.0,
    C1=1.0237674304864928,
    n1=16.454443290728882,
    C2=17.549434884804363,
    n2=0.4090052787333299,
)
