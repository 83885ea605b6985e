#!/usr/bin/python3
"""Where a coarse mesh's error comes from in the two-link deployment (paper sec. 5).

Linear modes of the arm held straight (joint 1 pinned to ground, joint 2 a free pin, no
springs), link data as examples/scenes.h's deploy_links(), for three discretisations
of each link:

  hermite  the library's flexible link: Hermite beam elements, lumped mass rho A l / 2
           per element end on the translation and beta rho A l^3 per element end on the
           rotation (beta = 1/78, the library's choice; docs/design.md)
  moment   the same stiffness, translational masses chosen so that the link's mass and
           its first and second moments are exact (ends m / (N + 1) (1/2 - 6 beta / N),
           interior the rest)
  rfe      the rigid-finite-element layout (Kruszewski, Wittbrodt): N + 1 rigid pieces
           (l/2, l, ..., l, l/2) joined at the segment midpoints by springs EI / l

against the converged reference: Hermite elements with the consistent mass, 160 per link.
It also prints the excess of the lumped link's rigid rotary inertia about its root,
m L^2 (1/6 + 2 beta) / N^2, that shifts the deployment in time.

Needs numpy and scipy (Debian: python3-numpy python3-scipy). Run: /usr/bin/python3
bench/coarse_modes.py. The numbers are quoted in docs/validation.md.
"""
import numpy as np
import scipy.linalg as sl

LENGTH = [1.006423, 0.9945]
EI = [20.5879, 20.3819]
MASS = [0.52334, 0.42958]
TIP = [1.2, 0.336]
TIP_J = [8.5948e-4, 9.256e-4]
BETA = 1.0 / 78.0


def element_stiffness(ei, l):
    """Hermite beam element (w_a, theta_a, w_b, theta_b)."""
    return ei / l**3 * np.array([[12, 6 * l, -12, 6 * l],
                                 [6 * l, 4 * l * l, -6 * l, 2 * l * l],
                                 [-12, -6 * l, 12, -6 * l],
                                 [6 * l, 2 * l * l, -6 * l, 4 * l * l]])


def element_consistent_mass(rho_a, l):
    return rho_a * l / 420 * np.array([[156, 22 * l, 54, -13 * l],
                                       [22 * l, 4 * l * l, 13 * l, -3 * l * l],
                                       [54, 13 * l, 156, -22 * l],
                                       [-13 * l, -3 * l * l, -22 * l, 4 * l * l]])


def lumped_masses(link, n, layout):
    """Translational node masses and rotary inertias of one link."""
    l = LENGTH[link] / n
    m = MASS[link]
    rho_a = m / LENGTH[link]
    jr = BETA * rho_a * l**3
    ends = [k == 0 or k == n for k in range(n + 1)]
    trans = [rho_a * l * (0.5 if e else 1.0) for e in ends]
    if layout == "moment" and n > 1:
        end_mass = m / (n + 1) * (0.5 - 6 * jr / (m * l * l))
        inner_mass = (m - 2 * end_mass) / (n - 1)
        trans = [end_mass if e else inner_mass for e in ends]
    rot = [jr * (1.0 if e else 2.0) for e in ends]
    return trans, rot


def hermite_modes(n, layout):
    """Frequencies (Hz) of the straight arm of Hermite links."""
    per_link = 2 * (n + 1)
    ndof = 2 * per_link
    K = np.zeros((ndof, ndof))
    M = np.zeros((ndof, ndof))
    for link in range(2):
        l = LENGTH[link] / n
        off = link * per_link
        ke = element_stiffness(EI[link], l)
        me = element_consistent_mass(MASS[link] / LENGTH[link], l)
        for e in range(n):
            idx = [off + 2 * e + i for i in range(4)]
            K[np.ix_(idx, idx)] += ke
            if layout == "consistent":
                M[np.ix_(idx, idx)] += me
        if layout != "consistent":
            trans, rot = lumped_masses(link, n, layout)
            for k in range(n + 1):
                M[off + 2 * k, off + 2 * k] += trans[k]
                M[off + 2 * k + 1, off + 2 * k + 1] += rot[k]
        M[off + 2 * n, off + 2 * n] += TIP[link]
        M[off + 2 * n + 1, off + 2 * n + 1] += TIP_J[link]
    # joint 1 pins link 1's root; joint 2 makes link 2's root follow link 1's tip
    keep = [i for i in range(ndof) if i not in (0, per_link)]
    T = np.zeros((ndof, len(keep)))
    for j, i in enumerate(keep):
        T[i, j] = 1
    T[per_link, keep.index(2 * n)] = 1
    w2 = sl.eigh(T.T @ K @ T, T.T @ M @ T, eigvals_only=True)
    return np.sqrt(np.abs(w2)) / (2 * np.pi)


def rfe_modes(n):
    """Frequencies (Hz) of the straight arm of rigid pieces (absolute piece angles)."""
    nq = 2 * (n + 1)
    rows, masses, inertias = [], [], np.zeros(nq)
    K = np.zeros((nq, nq))
    hinge = np.zeros(nq)   # transverse displacement of the current hinge, linear in q
    q = 0
    for link in range(2):
        l = LENGTH[link] / n
        rho_a = MASS[link] / LENGTH[link]
        k_bend = EI[link] / l
        for p in range(n + 1):
            lp = 0.5 * l if p in (0, n) else l
            centre = hinge.copy()
            centre[q] += 0.5 * lp
            rows.append(centre)
            masses.append(rho_a * lp)
            inertias[q] = rho_a * lp**3 / 12
            if p > 0:
                K[np.ix_([q - 1, q], [q - 1, q])] += k_bend * np.array([[1, -1], [-1, 1]])
            hinge = hinge.copy()
            hinge[q] += lp
            q += 1
        rows.append(hinge.copy())
        masses.append(TIP[link])
        inertias[q - 1] += TIP_J[link]
    B = np.array(rows)
    M = B.T @ np.diag(masses) @ B + np.diag(inertias)
    w2 = sl.eigh(K, M, eigvals_only=True)
    return np.sqrt(np.abs(w2)) / (2 * np.pi)


def main():
    ref = hermite_modes(160, "consistent")
    # the two lowest are the (near-)rigid motions about the pins
    print("reference (160 consistent Hermite elements per link): "
          + ", ".join("%.4f Hz" % f for f in ref[2:6]))
    print("error of the four lowest bending modes (%):")
    for n in (5, 10, 20):
        for layout in ("hermite", "moment", "rfe"):
            f = rfe_modes(n) if layout == "rfe" else hermite_modes(n, layout)
            errs = " ".join("%+7.3f" % (100 * (a / b - 1)) for a, b in zip(f[2:6], ref[2:6]))
            print("  N = %2d  %-8s %s" % (n, layout, errs))
    print("lumped links' excess rigid rotary inertia about the root, m L^2 (1/6 + 2 beta) / N^2:")
    for n in (5, 10, 20):
        share = [(1 / 6 + 2 * BETA) / n**2 / (1 / 3) for _ in range(2)]
        print("  N = %2d  %.2f %% of the bare link's m L^2 / 3" % (n, 100 * share[0]))


if __name__ == "__main__":
    main()
