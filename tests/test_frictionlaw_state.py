import numpy as np
import pytest

from frictionlaw import HistoryState


def test_trial_never_ratchets_and_commit_rollback():
    s = HistoryState(3)
    s.propose([1e8, 0.0, -5.0])
    s.propose([5e7, 2e8, 0.0])  # a later Newton iteration with lower pressure at node 0
    assert np.array_equal(s.p_hist, [0, 0, 0])
    assert np.array_equal(s.p_hist_trial, [5e7, 2e8, 0])  # from committed, not from the last trial
    s.commit()
    assert np.array_equal(s.p_hist, [5e7, 2e8, 0])
    s.propose([1e9, 1e9, 1e9])
    s.rollback()  # cut-back
    assert np.array_equal(s.p_hist_trial, s.p_hist)
    s.propose([1e7, 1e7, 1e7])  # unloading never lowers the history
    s.commit()
    assert np.array_equal(s.p_hist, [5e7, 2e8, 1e7])
    with pytest.raises(ValueError):
        s.p_hist[0] = 1.0  # read-only view


def test_grow_resize_and_remap():
    s = HistoryState(p_hist=[1.0, 2.0, 3.0])
    idx = s.grow(2)
    assert list(idx) == [3, 4] and np.array_equal(s.p_hist, [1, 2, 3, 0, 0])
    s.remap(np.array([4, 2, -1, 0]))
    assert np.array_equal(s.p_hist, [0, 3, 0, 1]) and np.array_equal(s.p_hist_trial, s.p_hist)
    s.resize(2)
    assert np.array_equal(s.p_hist, [0, 3])
    with pytest.raises(ValueError, match=r"index_map entries must be in \[-1, 1\]"):
        s.remap(np.array([0, 5]))
    with pytest.raises(ValueError, match="index_map must be a 1-D integer array"):
        s.remap(np.array([0.5]))


def test_restart_file_round_trip_and_errors(tmp_path):
    s = HistoryState(p_hist=np.linspace(0, 1e9, 7))
    s.propose(np.full(7, 2e9))  # trial state is not saved: only what was committed
    path = s.save(tmp_path / "restart.npz")
    t = HistoryState.load(path)
    assert np.array_equal(t.p_hist, np.linspace(0, 1e9, 7))
    assert [p.name for p in tmp_path.iterdir()] == ["restart.npz"]
    np.savez(tmp_path / "bad.npz", p_hist=np.zeros(2))
    with pytest.raises(ValueError, match="not a friction restart file"):
        HistoryState.load(tmp_path / "bad.npz")
    np.savez(
        tmp_path / "v4.npz",
        format=np.array("sbmf-friction-restart"),
        version=np.array(4),
        p_hist=np.zeros(2),
    )
    with pytest.raises(ValueError, match="unsupported restart version 4"):
        HistoryState.load(tmp_path / "v4.npz")
    # a version 3 file carries slope_f (the two-state flattening); without it, refused naming it
    np.savez(
        tmp_path / "v3.npz",
        format=np.array("sbmf-friction-restart"),
        version=np.array(3),
        p_hist=np.zeros(2),
        alpha_f=np.zeros(2),
    )
    with pytest.raises(ValueError, match="without slope_f"):
        HistoryState.load(tmp_path / "v3.npz")
    # a version 2 file (before the two-state flattening) reads with slope_f = 0
    np.savez(
        tmp_path / "v2ok.npz",
        format=np.array("sbmf-friction-restart"),
        version=np.array(2),
        p_hist=np.ones(2),
        alpha_f=np.full(2, 0.3),
    )
    old = HistoryState.load(tmp_path / "v2ok.npz")
    assert np.array_equal(old.alpha_f, [0.3, 0.3]) and np.array_equal(old.slope_f, [0.0, 0.0])
    # the two states go through the restart, commit, rollback and remap with p_hist
    f = HistoryState(p_hist=[1.0, 2.0], alpha_f=[0.2, 0.4], slope_f=[0.05, 0.0])
    g = HistoryState.load(f.save(tmp_path / "two.npz"))
    assert np.array_equal(g.slope_f, [0.05, 0.0]) and np.array_equal(g.alpha_f, [0.2, 0.4])
    s_c, s_t = g.slope_arrays()
    s_t[:] = [0.01, 0.02]
    g.rollback()
    assert np.array_equal(g.slope_f_trial, [0.05, 0.0])
    s_t[:] = [0.01, 0.02]
    g.commit()
    g.remap(np.array([1, -1, 0]))
    assert np.array_equal(g.slope_f, [0.02, 0.0, 0.01]) and np.array_equal(g.p_hist, [2, 0, 1])
    with pytest.raises(ValueError, match="slope_f must be finite and >= 0"):
        HistoryState(p_hist=[1.0], slope_f=[-0.1])
    # a version 2 file carries alpha_f; without it, it is refused naming it
    np.savez(
        tmp_path / "v2.npz",
        format=np.array("sbmf-friction-restart"),
        version=np.array(2),
        p_hist=np.zeros(2),
    )
    with pytest.raises(ValueError, match="without alpha_f"):
        HistoryState.load(tmp_path / "v2.npz")


def test_bad_input():
    with pytest.raises(ValueError, match="n_nodes must be >= 0"):
        HistoryState(-1)
    with pytest.raises(ValueError, match="p_hist must be >= 0"):
        HistoryState(p_hist=[-1.0])
    with pytest.raises(ValueError, match="p_hist must not contain NaN"):
        HistoryState(p_hist=[np.nan])
    with pytest.raises(ValueError, match=r"p must have shape \(2,\)"):
        HistoryState(2).propose([1.0, 2.0, 3.0])
