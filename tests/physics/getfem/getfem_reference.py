#!/usr/bin/python3
"""Static hyperelastic reference solutions with GetFEM.

    getfem_reference.py CASE OUT [STATS]

CASE is a whitespace-separated text file:

    law stvk | neo_hookean | mooney_rivlin | mooney_rivlin_nodal
    params lambda mu                 (stvk, neo_hookean)
    params c10 c01 kappa             (mooney_rivlin, mooney_rivlin_nodal)
    steps S                          load steps (the loads grow linearly to their full value)
    tolerance T                      optional: Newton's max_res [N] (default: 1e-12 of the
                                     residual at rest)
    runs R                           optional: solve the case R times from rest (default 1)
    nodes N      then N lines: x y z
    tets M       then M lines: four node indices (0-based)
    fixed K      then K lines: node component displacement
    forces K     then K lines: node component force

OUT receives one line per node: the displacement ux uy uz. STATS, where given, receives
"newton_iterations N", "solve_seconds S" and "solve_cpu_seconds C" (GetFEM's Newton solves
over every load step, of the last run). The problem is solved with P1
elements, a one-point rule (exact: F is constant per element), GetFEM's own finite-strain
potentials and its Newton solver; fixed dofs are held by Lagrange multipliers and nodal
forces enter as an explicit right-hand side, so both act on exactly the given dofs.

mooney_rivlin_nodal is the mixed displacement-pressure form of Tactus's volumetric = "nodal":
Pi(u, p) = int psi_iso + int p (J - 1) - int p^2 / (2 kappa), a P1 pressure beside the P1
displacement, the last term integrated at the vertices (IM_NC(3,1): the pressure's mass
lumped), the others by the one-point rule (exact: J is constant and p linear per element).
GetFEM solves the saddle-point system in u and p; Tactus condenses p and solves in u alone.
"""
import sys
import time

import numpy as np
import getfem as gf

# GetFEM's potentials, and the same densities written out: psi(F), F = Id + Grad_u.
#   stvk:          lambda/2 tr(E)^2 + mu E:E,  E = (F^T F - I)/2
#   neo_hookean:   mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2
#   mooney_rivlin: C10 (J^-2/3 I1 - 3) + C01 (J^-4/3 I2 - 3) + kappa/2 (J - 1)^2
# GetFEM's Compressible_Mooney_Rivlin has d1 (J - 1)^2, hence d1 = kappa / 2.
MACROS = {
    "F": "(Id(3) + Grad_u)",
    "E": "((F' * F - Id(3)) / 2)",
    "J": "Det(F)",
    "I1": "Norm_sqr(F)",
    "I2": "((sqr(Norm_sqr(F)) - Norm_sqr(F' * F)) / 2)",
}
LAWS = {
    "stvk": ("SaintVenant_Kirchhoff", "Saint_Venant_Kirchhoff_potential",
             lambda p: [p[0], p[1]],
             "p(1) / 2 * sqr(Trace(E)) + p(2) * Norm_sqr(E)"),
    "neo_hookean": ("Compressible_Neo_Hookean_Bonet", "Compressible_Neo_Hookean_Bonet_potential",
                    lambda p: [p[0], p[1]],
                    "p(2) / 2 * (I1 - 3) - p(2) * log(J) + p(1) / 2 * sqr(log(J))"),
    "mooney_rivlin": ("Compressible_Mooney_Rivlin", "Compressible_Mooney_Rivlin_potential",
                      lambda p: [p[0], p[1], p[2] / 2.0],
                      "p(1) * (pow(J, -2/3) * I1 - 3) + p(2) * (pow(J, -4/3) * I2 - 3)"
                      " + p(3) * sqr(J - 1)"),
    # The isochoric part; the volumetric one is the pressure's (solve()).
    "mooney_rivlin_nodal": ("Incompressible_Mooney_Rivlin", "Incompressible_Mooney_Rivlin_potential",
                            lambda p: [p[0], p[1]],
                            "p(1) * (pow(J, -2/3) * I1 - 3) + p(2) * (pow(J, -4/3) * I2 - 3)"),
}


def read_case(path):
    tokens = open(path).read().split()
    pos = 0

    def take(n=1):
        nonlocal pos
        pos += n
        return tokens[pos - n:pos]

    case = {"steps": 1, "runs": 1, "fixed": [], "forces": []}
    while pos < len(tokens):
        key = take()[0]
        if key == "law":
            case["law"] = take()[0]
        elif key == "params":
            n = 3 if case["law"].startswith("mooney_rivlin") else 2
            case["params"] = [float(t) for t in take(n)]
        elif key == "steps":
            case["steps"] = int(take()[0])
        elif key == "runs":
            case["runs"] = int(take()[0])
        elif key == "tolerance":
            case["tolerance"] = float(take()[0])
        elif key == "nodes":
            n = int(take()[0])
            case["nodes"] = np.array([float(t) for t in take(3 * n)]).reshape(n, 3)
        elif key == "tets":
            n = int(take()[0])
            case["tets"] = np.array([int(t) for t in take(4 * n)]).reshape(n, 4)
        elif key in ("fixed", "forces"):
            n = int(take()[0])
            case[key] = [(int(a), int(b), float(c)) for a, b, c in (take(3) for _ in range(n))]
        else:
            raise SystemExit(f"getfem_reference: unknown key '{key}' in {path}")
    return case


def solve(case):
    nodes, tets = case["nodes"], case["tets"]
    mesh = gf.Mesh("empty", 3)
    # GetFEM merges points by coordinates: build the convexes from the points themselves.
    mesh.add_convex(gf.GeoTrans("GT_PK(3,1)"), np.ascontiguousarray(nodes[tets].transpose(2, 1, 0)))
    mf = gf.MeshFem(mesh, 3)
    mf.set_classical_fem(1)
    mim = gf.MeshIm(mesh, gf.Integ("IM_TETRAHEDRON(1)"))
    ndof = mf.nbdof()
    if ndof != 3 * len(nodes):
        raise SystemExit(f"getfem_reference: {ndof} dofs for {len(nodes)} nodes")

    # Tactus node -> GetFEM dof of its x component (dofs come in xyz triples per node).
    dof_points = mf.basic_dof_nodes()[:, ::3].T
    d2 = ((nodes[:, None, :] - dof_points[None, :, :]) ** 2).sum(axis=2)  # small meshes only
    idx = d2.argmin(axis=1)
    dist = np.sqrt(d2[np.arange(len(nodes)), idx])
    size = np.ptp(nodes, axis=0).max()
    if dist.max() > 1e-9 * size or len(set(idx)) != len(nodes):
        raise SystemExit("getfem_reference: mesh nodes do not map one-to-one onto GetFEM dofs")
    dof = 3 * idx

    nodal = case["law"] == "mooney_rivlin_nodal"
    brick_law, potential, to_getfem, density = LAWS[case["law"]]
    params = to_getfem(case["params"])
    md = gf.Model("real")
    md.add_fem_variable("u", mf)
    md.add_initialized_data("p", params)
    md.add_finite_strain_elasticity_brick(mim, brick_law, "u", "p")
    if nodal:
        mf_p = gf.MeshFem(mesh, 1)
        mf_p.set_classical_fem(1)
        md.add_fem_variable("pressure", mf_p)
        md.add_initialized_data("kappa", case["params"][2])
        md.add_macro("F", MACROS["F"])
        md.add_nonlinear_term(mim, "pressure * Det(F) * (Inv(F)'):Grad_Test_u + (Det(F) - 1) * Test_pressure")
        vertices = gf.MeshIm(mesh, gf.Integ("IM_NC(3,1)"))
        md.add_linear_term(vertices, "-pressure * Test_pressure / kappa")

    fixed = case["fixed"]
    values = np.array([v for _, _, v in fixed])
    if fixed:
        B = gf.Spmat("empty", len(fixed), ndof)
        for row, (n, c, _) in enumerate(fixed):
            B[row, int(dof[n]) + c] = 1.0
        md.add_variable("lambda_D", len(fixed))
        ib = md.add_constraint_with_multipliers("u", "lambda_D", B, values)
    force = np.zeros(ndof)
    for n, c, v in case["forces"]:
        force[dof[n] + c] += v
    ir = md.add_explicit_rhs("u", force)

    # GetFEM's Newton stops on an absolute residual: take it relative to the residual of the
    # full load at rest (the load in N or, for prescribed displacements, the constraint rows).
    md.set_variable("u", np.zeros(ndof))
    md.assembly("build_rhs")
    tolerance = case.get("tolerance", 1e-12 * np.linalg.norm(md.rhs()))
    steps = case["steps"]
    runs = []
    for run in range(case["runs"]):
        # Each run from rest, the multipliers' included: the same Newton path every time.
        md.set_variable("u", np.zeros(ndof))
        if fixed:
            md.set_variable("lambda_D", np.zeros(len(fixed)))
        stats = {"newton_iterations": 0, "solve_seconds": 0.0, "solve_cpu_seconds": 0.0}
        runs.append(stats)
        for k in range(1, steps + 1):
            s = k / steps
            if fixed:
                md.set_private_rhs(ib, s * values)
            md.set_private_rhs(ir, s * force)
            # Newton with GetFEM's basic line search, the fastest here; where it fails (deep
            # compression in one step), again from the last solution with the simplest one.
            last = md.variable("u").copy()
            for search in ("basic", "simplest"):
                start, start_cpu = time.perf_counter(), time.process_time()
                nit, _ = md.solve("max_res", tolerance, "max_iter", 100, "lsearch", search)
                stats["solve_seconds"] += time.perf_counter() - start
                stats["solve_cpu_seconds"] += time.process_time() - start_cpu
                stats["newton_iterations"] += nit
                if nit < 100:
                    break
                md.set_variable("u", last)
            if nit >= 100:
                raise SystemExit(f"getfem_reference: Newton did not converge at load step {k}")
    if any(run["newton_iterations"] != runs[0]["newton_iterations"] for run in runs):
        raise SystemExit("getfem_reference: the runs from rest took different Newton iterations: "
                         + ", ".join(str(run["newton_iterations"]) for run in runs))
    stats = runs[-1]
    U = md.variable("u")

    # The potential GetFEM used must be the density written above, on the solution itself.
    # Where an element is inside out (the StVK path can end there) GetFEM's potential is not
    # defined; the displacements are still its Newton solution.
    x = nodes + U[dof[:, None] + np.arange(3)]

    def volumes(p):
        a, b, c = (p[tets[:, i]] - p[tets[:, 0]] for i in (1, 2, 3))
        return np.einsum("ij,ij->i", np.cross(a, b), c)

    if (volumes(x) / volumes(nodes)).min() <= 0.0:
        return U[dof[:, None] + np.arange(3)], stats
    for name, expr in MACROS.items():
        if not (nodal and name == "F"):
            md.add_macro(name, expr)
    e_getfem = gf.asm("generic", mim, 0, f"{potential}(Grad_u, p)", -1, md)
    e_written = gf.asm("generic", mim, 0, density, -1, md)
    if abs(e_getfem - e_written) > 1e-12 * abs(e_written):
        raise SystemExit(f"getfem_reference: GetFEM's {potential} ({e_getfem!r}) differs from the "
                         f"density written here ({e_written!r})")
    return U[dof[:, None] + np.arange(3)], stats


def main():
    if len(sys.argv) not in (3, 4):
        raise SystemExit("usage: getfem_reference.py CASE OUT [STATS]")
    gf.util_trace_level(0)
    u, stats = solve(read_case(sys.argv[1]))
    np.savetxt(sys.argv[2], u, fmt="%.17g")
    if len(sys.argv) == 4:
        with open(sys.argv[3], "w") as f:
            for key, value in stats.items():
                f.write(f"{key} {value}\n")


if __name__ == "__main__":
    main()
