"""The default calibration's parameters (halfspace-calib's built-in scene), as test inputs."""

DEFAULT = dict(
    m=0.5,
    sigma_y=285714285.71428573,
    H=800000000.0,
    C1=1.0466452593966644,
    n1=2.8674798599724576,
    C2=7.443848731746356,
    n2=0.5753816933748891,
)
