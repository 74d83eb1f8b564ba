"""The comparison baselines of the paper's Section 5, for benchmarks and studies.

- ``HermiteSimpson(model, dt, tol=1e-10, reuse_jacobian=True)``: Hermite-Simpson direct collocation
  used as an implicit simulator (simplified Newton within each step by default, as hovi's VIs);
  ``.rollout(q0, v0, steps)`` returns a dict with q, v, iterations, status, seconds.
- ``AutodiffDel(model, s, dt)``: the DEL residual, Newton direction (dense LU) and D^2 L_d by
  automatic differentiation of a scalar-templated Lagrangian.
- ``one_step_batch(model, dt, q0, qdot0, method)``: one trapezoidal step from many states by hovi's
  exact Newton ('newton'), the quasi-Newton of Lee et al. 2016 ('quasi_newton'), continuation in
  the step length ('continuation') or Newton with continuation when it fails
  ('newton+continuation'), timed in C++.
- ``fig3_batch(...)``: per-call times of the recursive algorithms or their AD counterparts.

They are compiled into their own extension, ``hovi._baselines``, beside the product ``hovi._core``.
"""
try:
    from ._baselines import AutodiffDel, HermiteSimpson, fig3_batch, one_step_batch
except ImportError as e:  # pragma: no cover - a build without the baselines
    raise ImportError(
        "hovi.baselines needs the extension hovi._baselines, which this build of hovi does not have: "
        "build with the CMake option HOVI_BUILD_BASELINES=ON (the default), e.g. `make build`") from e

__all__ = ["AutodiffDel", "HermiteSimpson", "fig3_batch", "one_step_batch"]
