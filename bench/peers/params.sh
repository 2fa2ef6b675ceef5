# Shared parameters of the peer benchmark (issue 10), sourced by make_bed.sh and run_peers.sh.
# Base values are the table's case; everything below "derived" is computed from them, and
# write_params() writes the lot as `variable NAME equal VALUE` lines that the LAMMPS and
# LIGGGHTS inputs `include`. docs/performance.md explains each derived value.

# --- the case (SI units) ---
: "${PEERS_DIAMETER:=0.005}"    # sphere diameter d [m]
: "${PEERS_DENSITY:=2500}"      # [kg/m^3] (as bench/bench_bed.c)
: "${PEERS_YOUNG:=1e7}"         # E [Pa], particles and walls alike
: "${PEERS_POISSON:=0.3}"       # nu
: "${PEERS_COR:=0.5}"           # coefficient of restitution e
: "${PEERS_FRICTION:=0.5}"      # sliding friction mu (pairs and walls)
: "${PEERS_ROLLING:=0.1}"       # rolling friction eta_r (pairs and walls)
: "${PEERS_GAMMA:=0.2}"         # JKR surface energy per surface gamma [J/m^2] (JKR bed)
: "${PEERS_SJKR_OVERLAP:=1e-5}"  # pair overlap [m] at which LIGGGHTS' sjkr matches JKR's adhesion
: "${PEERS_DT:=1e-5}"           # time step [s]
: "${PEERS_SKIN:=0.0005}"       # neighbour skin [m]
: "${PEERS_GRAVITY:=9.81}"      # [m/s^2], along -z
# LAMMPS' rolling spring is a constant k_roll (sds): model_c = adem's model C stiffness
# 2.25 eta_r^2 S_n, epsd2 = LIGGGHTS epsd2's k_t; both taken at the overlap delta_ref.
: "${PEERS_LAMMPS_KROLL:=model_c}"

# Writes the parameters, base and derived, as LAMMPS/LIGGGHTS `variable` lines to file $1.
write_params() {
  awk -v d="$PEERS_DIAMETER" -v rho="$PEERS_DENSITY" -v E="$PEERS_YOUNG" -v nu="$PEERS_POISSON" \
      -v e="$PEERS_COR" -v mu="$PEERS_FRICTION" -v mur="$PEERS_ROLLING" -v gam="$PEERS_GAMMA" \
      -v dt="$PEERS_DT" -v skin="$PEERS_SKIN" -v g="$PEERS_GRAVITY" -v kr="$PEERS_LAMMPS_KROLL" \
      -v dm="$PEERS_SJKR_OVERLAP" '
  function tsuji(c) {  # LAMMPS 29Sep2021 "damping tsuji": the COR it is given becomes this alpha
    return 1.2728 - 4.2783*c + 11.087*c^2 - 22.348*c^3 + 27.467*c^4 - 18.022*c^5 + 4.8218*c^6
  }
  function jkr_radius(delta,   lo, hi, k, c) {     # largest root of delta = a^2/R - 2 sqrt(pi gam a/Es) (H10)
    lo = (4*pi*gam*R^2/Es)^(1/3); hi = lo + 10*sqrt(R*delta) + 10*lo
    for (k = 0; k < 200; k++) { c = (lo + hi)/2; if (c^2/R - 2*sqrt(pi*gam*c/Es) < delta) lo = c; else hi = c }
    return (lo + hi)/2
  }
  function p(name, value, comment) { printf "variable %-12s equal %.12g   # %s\n", name, value, comment }
  BEGIN {
    pi = atan2(0, -1)
    r = d/2; R = r/2                                # sphere radius; pair effective radius
    m = rho*pi*d^3/6
    Es = E/(2*(1 - nu^2))                           # E* of two equal materials (H2)
    Gs = E/(4*(2 - nu)*(1 + nu))                    # G* of two equal materials (H15)
    beta = log(e)/sqrt(log(e)^2 + pi^2)             # H12
    alpha = sqrt(5)*(-beta)                         # adem damping as alpha*sqrt(m* (4/3)E* a)
    lo = 0; hi = 1                                  # invert the Tsuji polynomial (decreasing)
    for (k = 0; k < 200; k++) { c = (lo + hi)/2; if (tsuji(c) > alpha) lo = c; else hi = c }
    cor_lmp = (lo + hi)/2
    xgt = sqrt(4*Gs/Es)                             # tangential/normal damping ratio sqrt(S_t/S_n)
    A = 4/3*Es*sqrt(R)                              # Hertz F = A delta^1.5 (pair)
    dref = (m*g/A)^(2/3)                            # overlap of a pair contact loaded by one weight
    Snref = 2*Es*sqrt(R*dref)                       # its tangent stiffness S_n
    Stref = 8*Gs*sqrt(R*dref)                       # its tangential stiffness S_t
    if (kr == "model_c") kroll = 2.25*mur^2*Snref   # LAMMPS sds k_roll: adem model C k_r/R^2 there
    else if (kr == "epsd2") kroll = Stref           # LIGGGHTS epsd2 k_r/R^2 there
    else { print "params.sh: PEERS_LAMMPS_KROLL must be model_c or epsd2" > "/dev/stderr"; exit 1 }
    FC = 3*pi*gam*R                                 # JKR pull-off force (pair)
    a0 = (9*pi*gam*R^2/Es)^(1/3)                    # JKR equilibrium contact radius
    am = jkr_radius(dm)                             # JKR at the matching overlap dm:
    Fjkr = 4*Es*am^3/(3*R) - 4*sqrt(pi*gam*Es*am^3) #   its force (H8-H9)
    dF = A*dm^1.5 - Fjkr                            #   and how much less than Hertz it pushes
    ksjkr = dF/(2*pi*R*dm)                          # sjkr: k times the area 2 pi R delta
    kpull = (6.75*A^2*FC)^(1/3)/(2*pi*R)            # (the k that would match the pull-off force)
    p("diameter", d, "sphere diameter [m]")
    p("density", rho, "[kg/m^3]")
    p("young", E, "E [Pa]")
    p("poisson", nu, "nu")
    p("cor", e, "coefficient of restitution")
    p("friction", mu, "sliding friction")
    p("rolling", mur, "rolling friction eta_r")
    p("gamma", gam, "JKR surface energy per surface [J/m^2]")
    p("dt", dt, "time step [s]")
    p("skin", skin, "neighbour skin [m]")
    p("gravity", g, "[m/s^2]")
    p("mass", m, "sphere mass [kg]")
    p("estar", Es, "E* = E/(2(1-nu^2))")
    p("gstar", Gs, "G* = E/(4(2-nu)(1+nu))")
    p("beta", beta, "ln e/sqrt(ln^2 e + pi^2)")
    p("alpha", alpha, "sqrt(5)|beta|: adem damping = alpha sqrt(m* (4/3) E* a)")
    p("cor_lmp", cor_lmp, "COR to give LAMMPS damping tsuji so that its alpha = alpha")
    p("alpha_lmp", tsuji(cor_lmp), "LAMMPS alpha from cor_lmp (check)")
    p("xgammat", xgt, "LAMMPS tangential damping factor sqrt(4 G*/E*)")
    p("kt_lmp", 8*Gs, "LAMMPS mindlin k_t = 8 G* (pairs and walls)")
    p("young_wall_lmp", E/(1 + nu), "E given to LAMMPS walls: its wall code uses E/(2(1-nu))")
    p("kroll_lmp", kroll, "LAMMPS sds k_roll [N/m] (" kr "): model C 2.25 eta_r^2 S_n(delta_ref) = " 2.25*mur^2*Snref ", epsd2 S_t(delta_ref) = " Stref)
    p("delta_ref", dref, "pair overlap under one particle weight [m]")
    p("fc", FC, "JKR pull-off force 3 pi gamma R (pair) [N]")
    p("a0", a0, "JKR equilibrium contact radius (pair) [m]")
    p("delta0", a0^2/(3*R), "JKR equilibrium overlap (pair) [m]")
    p("bond", FC/(m*g), "F_C/(m g)")
    p("sjkr_overlap", dm, "pair overlap where sjkr and JKR pull equally [m]")
    p("jkr_pull", dF, "JKR adhesion there: Hertz force - JKR force [N]")
    p("ksjkr", ksjkr, "LIGGGHTS sjkr cohesion energy density [J/m^3] (pull-off match would be " kpull ")")
  }' > "$1"
}
