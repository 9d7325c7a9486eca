"""Adaptive Growing Neural Gas (paper 3.1 with its errata, docs/design.md §3.1)."""

from __future__ import annotations

from typing import Self

import numpy as np

from hsr_handover.topology._graph_state import GraphState
from hsr_handover.topology._network import GrowingNetwork
from hsr_handover.topology._neural_gas_kernels import train_neural_gas
from hsr_handover.topology._validation import check_int, check_real


class GrowingNeuralGas(GrowingNetwork):
    """Growing Neural Gas with distance-based neighbour learning and error-based deletion.

    One signal p (paper steps 1-7, primed GNG steps):

    1. winner s1 and runner-up s2 = the two nodes nearest to p (eqs. 12-13, argmin);
    2. link s1-s2 with age 0 (eq. 14);
    3. w_s1 += mu1 (p - w_s1) (eq. 2); each neighbour j: w_j += mu2 xi_j (p - w_j) with
       xi_j = exp(-mu3 ||p - w_j||) (eq. 3);
    4. age s1's edges by one (eq. 15), delete edges older than a_max and nodes left alone;
    5. E_s1 += ||p - w_s1||^2, measured before the move as in Fritzke's GNG (eq. 4);
    6. every lam signals, below max_nodes: new node between the node q of largest error and
       its neighbour f of largest error (eqs. 5-9);
    7. E_i -= beta E_i for all i (eq. 10); delete nodes with E_i < e_min and their edges
       (step 6'-ii), never going below two nodes.

    With mu3 = 0 and e_min = 0 this is Fritzke's GNG (1995), up to the order of steps 2 and 4:
    the paper ages the new s1-s2 edge in the same signal, so it leaves one signal earlier.

    Parameters
    ----------
    max_nodes : node limit (>= 2).
    lam : insertion interval lambda, in signals.
    mu1, mu2 : learning rates of the winner and of its neighbours, in [0, 1].
    mu3 : distance scale of xi_j in 1 / input units (0: neighbours all move by mu2).
    a_max : largest edge age kept (>= 1).
    alpha : error reduction of q and f at insertion, in [0, 1].
    beta : error decay per signal, in [0, 1).
    e_min : deletion threshold of the accumulated error (0: no deletion).
    random_state : seed or numpy Generator; equal seeds give equal maps.

    Attributes after learning: ``nodes``, ``edges``, ``edge_ages``, ``errors``, ``n_nodes``,
    ``n_signals_`` (signals learnt) and ``n_dropped_`` (non-finite points dropped).
    """

    def __init__(
        self,
        max_nodes: int = 300,
        lam: int = 100,
        mu1: float = 0.05,
        mu2: float = 0.006,
        mu3: float = 0.0,
        a_max: int = 50,
        alpha: float = 0.5,
        beta: float = 0.0005,
        e_min: float = 0.0,
        random_state: int | np.random.Generator | None = None,
    ) -> None:
        self._set_learning_params(max_nodes, 2, lam, mu1, mu2, mu3, alpha, beta, random_state)
        self.a_max = check_int("a_max", a_max, 1)
        self.e_min = check_real("e_min", e_min, 0.0)

    def fit(
        self, points: np.ndarray, n_signals: int | None = None, weights: np.ndarray | None = None
    ) -> Self:
        """Forget everything, then learn as ``partial_fit``."""
        self._reset()
        return self.partial_fit(points, n_signals, weights)

    def partial_fit(
        self, points: np.ndarray, n_signals: int | None = None, weights: np.ndarray | None = None
    ) -> Self:
        """Learn from one frame of points (n, d) and keep the map for the next frame.

        By default every point is learnt once in random order. With ``weights`` (attention),
        ``n_signals`` points (default n) are drawn with probability proportional to weight.
        Rows with NaN or inf (or a NaN weight) are dropped and counted in ``n_dropped_``;
        an empty input changes nothing.
        """
        signals = self._signals(points, n_signals, weights)
        if signals is None:
            return self
        array, _, order = signals
        if self._state is None:
            self._state = GraphState.empty(array.shape[1], self.max_nodes)
            self._state.seed_clique(array[self._rng.integers(0, array.shape[0], size=2)])
        self._run(self._learn, order, array)
        return self

    def _learn(self, order, state, dist, scratch, array) -> int:
        return train_neural_gas(
            array,
            order,
            state.positions,
            state.errors,
            state.neighbours,
            state.ages,
            state.degree,
            state.counters,
            state.scale,
            dist,
            scratch,
            self.max_nodes,
            self.lam,
            self.mu1,
            self.mu2,
            self.mu3,
            self.a_max,
            self.alpha,
            self.beta,
            self.e_min,
        )
