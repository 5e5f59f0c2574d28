#!/usr/bin/env python3
"""Three-element parameters for the clay_push scenario (plain Python, no packages).

Seed 002 identified a four-element model (b) for its clay: a spring E2 in series with
[a damper c2 in parallel with a Maxwell arm (E1, c1)]. Our edges are three-element
models: Voigt (k1 || c1) in series with a damper c2. This script finds the (k1, c1, c2)
whose 1-D stress response to the experiment's strain history (push 9.6 mm of 80 mm at
0.5 mm/s, hold 47.88 s) is closest in least squares to model (b) with seed 002's Table II
values, and prints the fit next to the naive mapping k1 = E1, c1 = c1, c2 = c2.
Run: python3 sim/scenarios/clay_push_fit.py
"""
import math

E1, E2, C1, C2 = 5.8388e4, 1.2353e5, 2.1091e7, 8.3402e5  # seed 002 Table II, model (b)
STRAIN_RATE = 0.5 / 80.0  # [1/s] push speed over block height
PUSH_S, HOLD_S = 19.2, 47.88
DT = 0.01  # [s] explicit steps; both models' fastest rate is below 0.2 1/s
STEPS = int((PUSH_S + HOLD_S) / DT)


def strain_rate(t):
    return STRAIN_RATE if t < PUSH_S else 0.0


def model_b_stress():
    """sigma = E2 (e - eY); c2 eY' = sigma - sigma_arm; sigma_arm' = E1 eY' - (E1/c1) sigma_arm."""
    e = e_y = s_arm = 0.0
    out = []
    for i in range(STEPS):
        e += strain_rate(i * DT) * DT
        e_y_rate = (E2 * (e - e_y) - s_arm) / C2
        s_arm += (E1 * e_y_rate - E1 / C1 * s_arm) * DT
        e_y += e_y_rate * DT
        out.append(E2 * (e - e_y))
    return out


def three_element_stress(k1, c1, c2):
    """docs/model.md in 1-D: d' = (c2 e' - k1 d) / (c1 + c2), sigma = k1 d + c1 d'."""
    d = 0.0
    out = []
    for i in range(STEPS):
        rate = strain_rate(i * DT)
        d_rate = (c2 * rate - k1 * d) / (c1 + c2)
        out.append(k1 * d + c1 * d_rate)
        d += d_rate * DT
    return out


REFERENCE = model_b_stress()


def rms_error(params):
    out = three_element_stress(*params)
    return math.sqrt(sum((a - b) ** 2 for a, b in zip(out, REFERENCE)) / STEPS)


def nelder_mead(f, x0, step, iterations):
    n = len(x0)
    pts = [list(x0)] + [[x0[j] + (step if j == i else 0.0) for j in range(n)] for i in range(n)]
    vals = [f(p) for p in pts]
    for _ in range(iterations):
        order = sorted(range(n + 1), key=lambda i: vals[i])
        pts, vals = [pts[i] for i in order], [vals[i] for i in order]
        centre = [sum(p[j] for p in pts[:-1]) / n for j in range(n)]
        reflected = [2 * centre[j] - pts[-1][j] for j in range(n)]
        fr = f(reflected)
        if fr < vals[0]:
            expanded = [3 * centre[j] - 2 * pts[-1][j] for j in range(n)]
            fe = f(expanded)
            pts[-1], vals[-1] = (expanded, fe) if fe < fr else (reflected, fr)
        elif fr < vals[-2]:
            pts[-1], vals[-1] = reflected, fr
        else:
            contracted = [0.5 * (centre[j] + pts[-1][j]) for j in range(n)]
            fc = f(contracted)
            if fc < vals[-1]:
                pts[-1], vals[-1] = contracted, fc
            else:
                pts = [pts[0]] + [[0.5 * (pts[0][j] + p[j]) for j in range(n)] for p in pts[1:]]
                vals = [vals[0]] + [f(p) for p in pts[1:]]
    return pts[0]


def main():
    # Search in log space: the parameters span orders of magnitude and must stay positive.
    log_fit = nelder_mead(lambda x: rms_error([math.exp(v) for v in x]),
                          [math.log(E2), math.log(1e5), math.log(C2)], 0.5, 400)
    fit = [math.exp(v) for v in log_fit]
    print("model (b) peak stress %.0f Pa, end of hold %.0f Pa" % (max(REFERENCE), REFERENCE[-1]))
    print("naive k1=E1, c1=c1, c2=c2: RMS error %.0f Pa" % rms_error([E1, C1, C2]))
    print("fit k1=%.5g Pa, c1=%.5g Pa s, c2=%.5g Pa s: RMS error %.0f Pa, (c1+c2)/k1 = %.0f s"
          % (fit[0], fit[1], fit[2], rms_error(fit), (fit[1] + fit[2]) / fit[0]))


if __name__ == "__main__":
    main()
