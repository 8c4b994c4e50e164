"""The tip of a gently curved front on the lattice, linearised in its curvature: a chain.

A front of curvature kappa moving at c along a lattice direction reaches the blocks beside
a block later than the block itself (arrival time T = (n + kappa s^2/2)/c, n the normal
and s the tangential coordinate). To first order in kappa a neighbour's displacement is
the planar one delayed, U(t - Delta) = U(t) - Delta U_t(t), so the curved front's row of
blocks obeys a chain with two extra terms (docs/theory.md, section 7):

- along an axis the two neighbours across the front have the block's own phase, delayed
  by Delta = kappa dy^2/(2c): an extra drag -(kappa/c) u_t on the block's own velocity;
- along the diagonal (dx = dy) the four neighbours sit half a diagonal spacing ahead or
  behind, each delayed by kappa dx^2/(4c): the chain at spacing h = dx/sqrt(2) whose
  neighbour values are u - delta u_t, delta = kappa h^2/(2c).

This module integrates that chain on its own (numpy, classical RK4, each slip located by
bisection of the step), independently of the Rust engine. Blocks slip once and keep
sliding: the front is supersonic, so nothing behind it reaches the stuck blocks ahead,
and re-sticking behind cannot change its speed.
"""

from __future__ import annotations

import numpy as np


def front_speed(
    u_plus: float,
    gamma: float,
    h: float,
    *,
    drag: float = 0.0,
    delay: float = 0.0,
    blocks: int = 170,
    window: tuple[int, int] = (80, 160),
    steps_per_slip: int = 40,
) -> tuple[float, float]:
    """The steady speed of a front on the chain u_tt = (w_{n+1} + w_{n-1} - 2 u_n)/h^2
    - u_n - (2 gamma + drag) u_t with w = u - delay u_t (v = 0, uniform u_+ ahead).

    Returns (c, change): c from a line through the slip times of the window's blocks
    against their positions, and the change of c between the window's two halves (the
    steadiness of the measurement).
    """
    n = int(blocks)
    u = np.full(n, float(u_plus))
    v = np.zeros(n)
    sliding = np.zeros(n, bool)
    slip_time = np.full(n, np.nan)
    sliding[:3] = True  # three blocks released at t = 0 start the front
    slip_time[:3] = 0.0
    inv = 1.0 / (h * h)
    damp = 2.0 * gamma + drag
    dt = h / (1.3 * steps_per_slip)

    def accel(u, v):
        w = u - delay * v
        lap = np.empty_like(u)
        lap[1:-1] = w[2:] + w[:-2] - 2.0 * u[1:-1]
        lap[0] = w[1] - u[0]
        lap[-1] = w[-2] - u[-1]
        a = lap * inv - u - damp * v
        a[~sliding] = 0.0
        return a

    def velocity(v):
        return np.where(sliding, v, 0.0)

    def step(u, v, tau):
        k1u, k1v = velocity(v), accel(u, v)
        k2u = velocity(v + 0.5 * tau * k1v)
        k2v = accel(u + 0.5 * tau * k1u, v + 0.5 * tau * k1v)
        k3u = velocity(v + 0.5 * tau * k2v)
        k3v = accel(u + 0.5 * tau * k2u, v + 0.5 * tau * k2v)
        k4u = velocity(v + tau * k3v)
        k4v = accel(u + tau * k3u, v + tau * k3v)
        return (
            u + tau / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u),
            v + tau / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
        )

    def phi(u, v, k):
        w = u - delay * v
        return u[k] - (w[k + 1] + w[k - 1] - 2.0 * u[k]) * inv

    t = 0.0
    k = 3  # the first stuck block: the only one that can slip next
    while k < n - 2:
        un, vn = step(u, v, dt)
        if phi(un, vn, k) < 1.0:
            u, v, t = un, vn, t + dt
            continue
        lo, hi = 0.0, dt
        for _ in range(44):
            mid = 0.5 * (lo + hi)
            if phi(*step(u, v, mid), k) >= 1.0:
                hi = mid
            else:
                lo = mid
        u, v = step(u, v, hi)
        t += hi
        sliding[k] = True
        slip_time[k] = t
        k += 1
    idx = np.arange(*window)
    x = idx * h
    ts = slip_time[idx]
    half = idx.size // 2
    c = 1.0 / np.polyfit(x, ts, 1)[0]
    c1 = 1.0 / np.polyfit(x[:half], ts[:half], 1)[0]
    c2 = 1.0 / np.polyfit(x[half:], ts[half:], 1)[0]
    return float(c), float(c2 - c1)
