"""
Symbolic conditions
===================

Derive the IM and DKP conditions of the appendix four-bar symbolically (sympy), in link angles,
and the five-bar's type-1 (DKP-output) locus as implicit polynomials in the coordinates of its
end point.
"""
# %%
import symkin

mech = symkin.catalogue.get("fourbar_appendix")
sm = symkin.symbolic_model(mech, coordinates="angles")
print(sm.G.shape)
print("IM:", sm.im_condition().readable)
print("DKP-input:", sm.dkp_condition("input").readable)

# %%
# Singularity loci as implicit polynomials in (x_P, y_P): circles centred at the pivots.
loci = symkin.implicit_loci(symkin.catalogue.get("five_bar"), ("velocity:P.x", "velocity:P.y"),
                            kinds=("DKP-output",))
for f in loci["DKP-output"].factors:
    print(f.polynomial, "|", f.meaning)
