C=======================================================================
C     Abaqus/Explicit user subroutine VFRICTION (general contact;
C     argument list of the Abaqus User Subroutines Reference). One call
C     per block of nBlock contact points. state(i, j, k): variable i of
C     state node j of contact point k (nNodState = 1 for node-type
C     secondary surfaces, > 1 for edge-type ones):
C       1 = p_hist, 2 = cached -ln alpha1(p_hist) (optional), 3 = status
C       of the last call (optional). p = fNormal/areaCont. The contact
C     point's p_hist is the largest of its state nodes'; each state node
C     keeps max(its p_hist, p). Force limit tau(p, p_hist) areaCont;
C     stick when tau > 0 and the stick force is within it, otherwise
C     slip (tau = 0: no force, status slip, as traction_update).
C     Explicit has no iterations: each increment commits.
C     props(1) (*FRICTION, USER=VFRICTION, PROPERTIES=1 and its data
C     line) states the deck's unit system: 1 SI (Pa, m), 2 mm-t-s
C     (MPa, mm). Guards (docs/fe_codes.md): nStates >= 1, props(1) =
C     the unit system this routine was exported for, p <= 100 H, else
C     an error message ({{ host.message_routine }}) and {{ host.exit_routine }}; p beyond
C     the calibrated range: one warning per process.
{% if zones %}
C     Zones: the law of the name in {{ zones.key.argument }}, compared trimmed
C     and case-insensitive; {% if zones.default %}a name no zone gives runs the
C     default law{% else %}a name no zone gives stops the run (no
C     default law){% endif %}. state(4,j,k) = the law that
C     wrote the cache (DEPVAR >= 4); p_hist carries over between zones.
{% endif %}
{% from "core/zone_pick.f" import pick with context %}
C=======================================================================
      subroutine vfriction(
C Write only -
     1 fTangential,
C Read/Write -
     2 state,
C Read only -
     3 nBlock, nBlockAnal, nBlockEdge,
     4 nNodState, nNodSlv, nNodMst,
     5 nFricDir, nDir,
     6 nStates, nProps, nTemp, nFields,
     7 jFlags, rData,
     8 surfInt, surfSlv, surfMst,
     9 jConSlvUid, jConMstUid, props,
     1 dSlipFric, fStickForce, fTangPrev, fNormal,
     2 areaCont, dircosN, dircosSl,
     3 shapeSlv, shapeMst,
     4 coordSlv, coordMst,
     5 velSlv, velMst,
     6 tempSlv, tempMst,
     7 fieldSlv, fieldMst)
C
      include 'vaba_param.inc'
C
      dimension fTangential(nFricDir,nBlock),
     1 state(nStates,nNodState,nBlock),
     2 jConSlvUid(nNodSlv,nBlock),
     3 jConMstUid(nNodMst,nBlockAnal),
     4 props(nProps),
     5 dSlipFric(nDir,nBlock),
     6 fStickForce(nBlock),
     7 fTangPrev(nDir,nBlock),
     8 fNormal(nBlock),
     9 areaCont(nBlock),
     1 dircosN(nDir,nBlock),
     2 dircosSl(nDir,nBlock),
     3 shapeSlv(nNodSlv,nBlockEdge),
     4 shapeMst(nNodMst,nBlockAnal),
     5 coordSlv(nDir,nNodSlv,nBlock),
     6 coordMst(nDir,nNodMst,nBlockAnal),
     7 velSlv(nDir,nNodSlv,nBlock),
     8 velMst(nDir,nNodMst,nBlockAnal),
     9 tempSlv(nBlock),
     1 tempMst(nBlockAnal),
     2 fieldSlv(nFields,nBlock),
     3 fieldMst(nFields,nBlockAnal)
      dimension jFlags(*), rData(*)
      character*80 surfInt, surfSlv, surfMst
C
      double precision p, ph, g1h, g1new, tlim, dtau, flim, phnew, sj
      integer k, j, ia, istat, jmax
{% if zones %}
      integer SBMF_ZONE
      external SBMF_ZONE
{% endif %}
{% include "core/guard_decl.f" %}
C
{% if guards %}
C     guards: the deck's state variables and unit system
      if (nStates .lt. 1) then
        call SBMF_GUARD(1, dble(nStates))
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
        do k = 1, nBlock
          do ia = 1, nFricDir
            fTangential(ia, k) = 0.0d0
          end do
        end do
        return
{% endcall %}
{% endif %}
      do k = 1, nBlock
        do ia = 1, nFricDir
          fTangential(ia, k) = 0.0d0
        end do
        p = 0.0d0
C       an overflowing pressure is taken as the largest double
        if (areaCont(k) .gt. 0.0d0) then
          p = min(fNormal(k)/areaCont(k), huge(p))
        end if
{% if guards %}
        if (p .gt. SBMFPU) then
          call SBMF_GUARD(4{{ " + KZ" if zones else "" }}, p)
          return
        end if
        if (p .gt. SBMFPM) call SBMF_GUARD(5{{ " + KZ" if zones else "" }}, p)
{% endif %}
        if (.not. (p .gt. 0.0d0)) then
C         open (or no area): no friction, history unchanged
          if (nStates .ge. 3) then
            do j = 1, nNodState
              state(3, j, k) = 0.0d0
            end do
          end if
        else
          ph = 0.0d0
          jmax = 1
          do j = 1, nNodState
            if (state(1, j, k) .gt. ph) then
              ph = state(1, j, k)
              jmax = j
            end if
          end do
          g1h = -1.0d0
{% if zones %}
          if (nStates .ge. 4) then
            if (state(4, jmax, k) .eq. dble(iz)) g1h = state(2, jmax, k)
          end if
          call SBMF_ZSHEAR(iz, p, ph, g1h, tlim, dtau, g1new)
{% else %}
          if (nStates .ge. 2) g1h = state(2, jmax, k)
          call SBMF_SHEAR(p, ph, g1h, tlim, dtau, g1new)
{% endif %}
          flim = tlim*areaCont(k)
          if (tlim .gt. 0.0d0 .and. fStickForce(k) .le. flim) then
            fTangential(1, k) = -fStickForce(k)
            istat = 1
          else
            fTangential(1, k) = -flim
            istat = 2
          end if
          phnew = max(ph, p)
          do j = 1, nNodState
            sj = max(state(1, j, k), 0.0d0)
            if (nStates .ge. 2) then
C             the cache belongs to phnew; a node raised to p < phnew
C             gets 0 ("recompute")
              if (max(sj, p) .eq. phnew) then
                state(2, j, k) = g1new
{% if zones %}
                if (nStates .ge. 4) state(4, j, k) = dble(iz)
{% endif %}
              else if (p .gt. sj) then
                state(2, j, k) = 0.0d0
              end if
            end if
            state(1, j, k) = max(sj, p)
            if (nStates .ge. 3) state(3, j, k) = dble(istat)
          end do
        end if
      end do
      return
      end
C
{% include host.guards %}
{% include "core/sbmf_core.f" %}
