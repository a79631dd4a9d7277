{#
  The workpiece's flow curve baked in by --flow-curve (LS-DYNA's usrfrc and the patched
  CalculiX pass the element's plastic strain, not its flow stress or hardening):
  frictionlaw.flow_curve's SwiftCurve or TabulatedCurve statement by statement, but that a
  table's last segment continues beyond its last strain (as LS-DYNA continues its load curves)
  where the Python curve refuses. Context:
  flow, the export's FlowSpec (frictionlaw.export._flat, host stress unit).
#}
C=======================================================================
C     The workpiece's flow stress SIGY and hardening modulus HMOD =
C     d SIGY / d E at the equivalent plastic strain E (>= 0), host
C     stress unit: {{ flow.describe }}
{% if flow.form == "swift" %}
C     (Swift: SIGY = K (E0 + E)**N).
{% else %}
C     (points joined by straight lines; HMOD the slope of the segment
C     holding E, the segment above a point; beyond the last strain
C     the last segment continues).
{% endif %}
C=======================================================================
      SUBROUTINE SBMF_FLOW(E, SIGY, HMOD)
      IMPLICIT NONE
      DOUBLE PRECISION E, SIGY, HMOD
{% if flow.form == "swift" %}
      DOUBLE PRECISION K, E0, N
      PARAMETER (K = {{ flow.K | double }})
      PARAMETER (E0 = {{ flow.eps0 | double }})
      PARAMETER (N = {{ flow.n | double }})
      SIGY = K*(E0 + E)**N
      HMOD = N*K*(E0 + E)**(N - 1.0D0)
{% else %}
      INTEGER NF, J
      PARAMETER (NF = {{ flow.strain | length }})
      DOUBLE PRECISION FE(NF), FS(NF)
      PARAMETER (FE = (/
     &  {{ flow.strain | map("double") | join(",
     &  ") }} /))
      PARAMETER (FS = (/
     &  {{ flow.stress | map("double") | join(",
     &  ") }} /))
      J = 1
      DO WHILE (J .LT. NF - 1 .AND. .NOT. (E .LT. FE(J + 1)))
        J = J + 1
      END DO
      HMOD = (FS(J + 1) - FS(J))/(FE(J + 1) - FE(J))
      SIGY = FS(J) + HMOD*(E - FE(J))
{% endif %}
      RETURN
      END
C
