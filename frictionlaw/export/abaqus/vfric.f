C=======================================================================
C     Abaqus/Explicit user subroutine VFRIC (documented argument list).
C     statev(1,n) = p_hist of secondary (slave) node n, statev(2,n) =
C     cached -ln alpha1(p_hist) (optional), statev(3,n) = last status
C     (optional). Explicit has no iterations: each increment commits.
C     p = fNormal/areaSec; the force limit tau(p, p_hist) areaSec;
C     stick when tau > 0 and the stick force is within it, otherwise
C     slip (tau = 0: no force, status slip, as traction_update).
C     props(1) (*FRICTION, USER=VFRIC, PROPERTIES=1 and its data line)
C     states the deck's unit system: 1 SI (Pa, m), 2 mm-t-s (MPa, mm).
C     Guards (docs/fe_codes.md): nStateVar >= 1, props(1) = the unit
C     system this routine was exported for, p <= 100 H, else an error
C     message ({{ host.message_routine }}) and {{ host.exit_routine }}; p beyond the
C     calibrated range: one warning per process.
{% if zones %}
C     Zones: the law of the name in {{ zones.key.argument }}, compared trimmed
C     and case-insensitive; {% if zones.default %}a name no zone gives runs the
C     default law{% else %}a name no zone gives stops the run (no
C     default law){% endif %}. statev(4,n) = the law that
C     wrote the cache (DEPVAR >= 4); p_hist carries over between zones.
{% endif %}
{% from "core/zone_pick.f" import pick with context %}
C=======================================================================
      subroutine vfric(
C Write only -
     1 fTangential,
C Read/Write -
     2 statev,
C Read only -
     3 kStep, kInc, nContact, nFacNod, nSecNod, nMainNod,
     4 nFricDir, nDir, nStateVar, nProps, nTemp, nPred, numDefTfv,
     5 jSecUid, jMainUid, jConSecid, jConMainid, timStep, timGlb,
     6 dTimCur, surfInt, surfSec, surfMain, lContType,
     7 dSlipFric, fStickForce, fTangPrev, fNormal, frictionWork,
     8 shape, coordSec, coordMain, dirCosSl, dirCosN, props,
     9 areaSec, tempSec, preDefSec, tempMain, preDefMain)
C
      include 'vaba_param.inc'
C
      character*80 surfInt, surfSec, surfMain
C
      dimension props(nProps), statev(nStateVar,nSecNod),
     1 dSlipFric(nDir,nContact),
     2 fTangential(nFricDir,nContact),
     3 fTangPrev(nDir,nContact),
     4 fStickForce(nContact), areaSec(nSecNod),
     5 fNormal(nContact), shape(nFacNod,nContact),
     6 coordSec(nDir,nSecNod), coordMain(nDir,nMainNod),
     7 dirCosSl(nDir,nContact), dirCosN(nDir,nContact),
     8 jSecUid(nSecNod), jMainUid(nMainNod),
     9 jConSecid(nContact), jConMainid(nFacNod,nContact),
     1 tempSec(nContact), preDefSec(nContact,nPred),
     2 tempMain(numDefTfv), preDefMain(numDefTfv,nPred)
C
      double precision p, ph, g1h, g1new, tlim, dtau, flim
      integer k, n, ia, istat
{% if zones %}
      integer SBMF_ZONE
      external SBMF_ZONE
{% endif %}
{% include "core/guard_decl.f" %}
C
{% if guards %}
C     guards: the deck's state variables and unit system
      if (nStateVar .lt. 1) then
        call SBMF_GUARD(1, dble(nStateVar))
        return
      end if
      if (nProps .lt. 1) then
        call SBMF_GUARD(2, 0.0d0)
        return
      end if
      if (props(1) .ne. SBMFU) then
        call SBMF_GUARD(3, dble(props(1)))
        return
      end if
{% endif %}
{% if zones %}
{% call pick("SBMF_ZONE(" ~ zones.key.argument ~ ")", zones.key.argument) %}
        do k = 1, nContact
          do ia = 1, nFricDir
            fTangential(ia, k) = 0.0d0
          end do
        end do
        return
{% endcall %}
{% endif %}
      do k = 1, nContact
        n = jConSecid(k)
        do ia = 1, nFricDir
          fTangential(ia, k) = 0.0d0
        end do
C       an overflowing pressure is taken as the largest double
        p = min(fNormal(k)/areaSec(n), huge(p))
{% if guards %}
        if (p .gt. SBMFPU) then
          call SBMF_GUARD(4{{ " + KZ" if zones else "" }}, p)
          return
        end if
        if (p .gt. SBMFPM) call SBMF_GUARD(5{{ " + KZ" if zones else "" }}, p)
{% endif %}
        ph = statev(1, n)
        g1h = -1.0d0
{% if zones %}
        if (nStateVar .ge. 4) then
          if (statev(4, n) .eq. dble(iz)) g1h = statev(2, n)
        end if
{% else %}
        if (nStateVar .ge. 2) g1h = statev(2, n)
{% endif %}
        if (.not. (p .gt. 0.0d0)) then
          if (nStateVar .ge. 3) statev(3, n) = 0.0d0
        else
{% if zones %}
          call SBMF_ZSHEAR(iz, p, ph, g1h, tlim, dtau, g1new)
{% else %}
          call SBMF_SHEAR(p, ph, g1h, tlim, dtau, g1new)
{% endif %}
          flim = tlim*areaSec(n)
          if (tlim .gt. 0.0d0 .and. fStickForce(k) .le. flim) then
            fTangential(1, k) = -fStickForce(k)
            istat = 1
          else
            fTangential(1, k) = -flim
            istat = 2
          end if
          statev(1, n) = max(ph, p)
          if (nStateVar .ge. 2) statev(2, n) = g1new
          if (nStateVar .ge. 3) statev(3, n) = dble(istat)
{% if zones %}
          if (nStateVar .ge. 4) statev(4, n) = dble(iz)
{% endif %}
        end if
      end do
      return
      end
C
{% include host.guards %}
{% include "core/sbmf_core.f" %}
