"""The literature the project implements, cited in docstrings by these keys.

Docstrings write "eq. B.1 of [Carcione2022]_"; the full references are defined once here and
written into every dataset's ``references`` attribute by the scene runner.
"""

from __future__ import annotations

__all__ = ["REFERENCES", "cite"]

REFERENCES: dict[str, str] = {
    "Carcione2022": (
        "Carcione, J. M., Gei, D., Picotti, S., Qadrouh, A. N., Alajmi, M., and Ba, J., 2022. "
        "Rock acoustics of diagenesis and cementation. Pure and Applied Geophysics."
    ),
    "Carcione2005": (
        "Carcione, J. M., Helle, H. B., Santos, J. E., and Ravazzoli, C. L., 2005. A constitutive "
        "equation and generalized Gassmann modulus for multimineral porous media. Geophysics 70, "
        "N17-N26."
    ),
    "Berryman1980": (
        "Berryman, J. G., 1980. Long-wavelength propagation in composite elastic media II. "
        "Ellipsoidal inclusions. J. Acoust. Soc. Am. 68, 1820-1831."
    ),
    "Mavko2009": (
        "Mavko, G., Mukerji, T., and Dvorkin, J., 2009. The Rock Physics Handbook, 2nd ed. "
        "Cambridge University Press."
    ),
    "DvorkinNur1996": (
        "Dvorkin, J., and Nur, A., 1996. Elasticity of high-porosity sandstones: theory for two "
        "North Sea data sets. Geophysics 61, 1363-1370."
    ),
    "Dvorkin1994": (
        "Dvorkin, J., Nur, A., and Yin, H., 1994. Effective properties of cemented granular "
        "material. Mechanics of Materials 18, 351-366."
    ),
    "HanGuo": (
        "Han, X., and Guo, J. Influence of contact thickness on the acoustic velocities of loose "
        "sandstone and its application. SEG Technical Program Expanded Abstracts."
    ),
    "Xu2023": (
        "Xu, X., 2023. DEM validation of contact-bonding and distant-bonding cement in weakly "
        "cemented sandstones. ACS Omega. doi:10.1021/acsomega.3c03802."
    ),
    "Avseth2016": (
        "Avseth, P., Skjei, N., and Mavko, G., 2016. Rock-physics modeling of stress sensitivity "
        "and 4D time shifts in patchy cemented sandstones. The Leading Edge 35, 868-878."
    ),
    "Avseth2000": (
        "Avseth, P., Dvorkin, J., Mavko, G., and Rykje, J., 2000. Rock physics diagnostic of North "
        "Sea sands: link between microstructure and seismic properties. GRL 27, 2761-2764."
    ),
    "Krief1990": (
        "Krief, M., Garat, J., Stellingwerff, J., and Ventre, J., 1990. A petrophysical "
        "interpretation using the velocities of P and S waves. The Log Analyst 31, 355-369."
    ),
    "Gassmann1951": (
        "Gassmann, F., 1951. Über die Elastizität poröser Medien. Vierteljahrsschrift der "
        "Naturforschenden Gesellschaft in Zürich 96, 1-23."
    ),
    "BrownKorringa1975": (
        "Brown, R. J. S., and Korringa, J., 1975. On the dependence of the elastic properties of "
        "a porous rock on the compressibility of the pore fluid. Geophysics 40, 608-616."
    ),
    "Thomsen1986": (
        "Thomsen, L., 1986. Weak elastic anisotropy. Geophysics 51, 1954-1966."
    ),
    "HashinShtrikman1963": (
        "Hashin, Z., and Shtrikman, S., 1963. A variational approach to the theory of the elastic "
        "behaviour of multiphase materials. J. Mech. Phys. Solids 11, 127-140."
    ),
    "GarciaMedina2007": (
        "García, X., and Medina, E., 2007. Acoustic response of cemented granular sedimentary "
        "rocks: molecular dynamics modeling. Physical Review E 75, 061308."
    ),
    "Johnson1985": (
        "Johnson, K. L., 1985. Contact Mechanics. Cambridge University Press."
    ),
    "Walton1987": (
        "Walton, K., 1987. The effective elastic moduli of a random packing of spheres. "
        "J. Mech. Phys. Solids 35, 213-226."
    ),
    "GangiCarlson1996": (
        "Gangi, A. F., and Carlson, R. L., 1996. An asperity-deformation model for effective "
        "pressure. Tectonophysics 256, 241-251."
    ),
    "SquireTrapp1998": (
        "Squire, W., and Trapp, G., 1998. Using complex variables to estimate derivatives of real "
        "functions. SIAM Review 40, 110-112."
    ),
    "White1980": (
        "White, H., 1980. A heteroskedasticity-consistent covariance matrix estimator and a "
        "direct test for heteroskedasticity. Econometrica 48, 817-838."
    ),
    "Carroll1988": (
        "Carroll, R. J., and Ruppert, D., 1988. Transformation and Weighting in Regression. "
        "Chapman and Hall, New York."
    ),
    "BatzleWang1992": (
        "Batzle, M., and Wang, Z., 1992. Seismic properties of pore fluids. Geophysics 57, "
        "1396-1408."
    ),
    "KleisSanchez1990": (
        "Kleis, S. J., and Sanchez, L. A., 1990. Dependence of speed of sound on salinity and "
        "temperature in concentrated NaCl solutions. Solar Energy 45, 201-206."
    ),
    "SpanWagner1996": (
        "Span, R., and Wagner, W., 1996. A new equation of state for carbon dioxide covering the "
        "fluid region from the triple-point temperature to 1100 K at pressures up to 800 MPa. "
        "J. Phys. Chem. Ref. Data 25, 1509-1596."
    ),
    "SetzmannWagner1991": (
        "Setzmann, U., and Wagner, W., 1991. A new equation of state and tables of thermodynamic "
        "properties for methane covering the range from the melting line to 625 K at pressures "
        "up to 1000 MPa. J. Phys. Chem. Ref. Data 20, 1061-1155."
    ),
    "Wood1955": ("Wood, A. B., 1955. A Textbook of Sound. Bell, London."),
    "Brie1995": (
        "Brie, A., Pampuri, F., Marsala, A. F., and Meazza, O., 1995. Shear sonic interpretation "
        "in gas-bearing sands. SPE Annual Technical Conference, SPE 30595."
    ),
    "Standing1947": (
        "Standing, M. B., 1947. A pressure-volume-temperature correlation for mixtures of "
        "California oils and gases. Drilling and Production Practice, API, 275-287."
    ),
    "AkiRichards1980": (
        "Aki, K., and Richards, P. G., 1980. Quantitative Seismology, vol. 1. Freeman, San "
        "Francisco."
    ),
    "Zoeppritz1919": (
        "Zoeppritz, K., 1919. Erdbebenwellen VII. VIIb. Über Reflexion und Durchgang seismischer "
        "Wellen durch Unstetigkeitsflächen. Nachrichten der Königlichen Gesellschaft der "
        "Wissenschaften zu Göttingen, Mathematisch-physikalische Klasse, 66-84."
    ),
    "Shuey1985": (
        "Shuey, R. T., 1985. A simplification of the Zoeppritz equations. Geophysics 50, 609-614."
    ),
    "RutherfordWilliams1989": (
        "Rutherford, S. R., and Williams, R. H., 1989. Amplitude-versus-offset variations in gas "
        "sands. Geophysics 54, 680-688."
    ),
    "RossKinman1995": (
        "Ross, C. P., and Kinman, D. L., 1995. Nonbright-spot AVO: two examples. Geophysics 60, "
        "1398-1408."
    ),
    "CastagnaSwan1997": (
        "Castagna, J. P., and Swan, H. W., 1997. Principles of AVO crossplotting. The Leading "
        "Edge 16, 337-342."
    ),
    "Castagna1998": (
        "Castagna, J. P., Swan, H. W., and Foster, D. J., 1998. Framework for AVO gradient and "
        "intercept interpretation. Geophysics 63, 948-956."
    ),
    "Hilterman2001": (
        "Hilterman, F. J., 2001. Seismic Amplitude Interpretation. SEG/EAGE Distinguished "
        "Instructor Short Course 4."
    ),
    "Ricker1953": (
        "Ricker, N., 1953. The form and laws of propagation of seismic wavelets. Geophysics 18, "
        "10-40."
    ),
    "Yilmaz2001": (
        "Yilmaz, O., 2001. Seismic Data Analysis. Society of Exploration Geophysicists, Tulsa."
    ),
    "AvsethLehocki2016": (
        "Avseth, P., and Lehocki, I., 2016. Combining burial history and rock-physics modeling to "
        "constrain AVO analysis during exploration. The Leading Edge 35, 528-534."
    ),
    "IAPWS1997": (
        "Wagner, W., et al., 2000. The IAPWS industrial formulation 1997 for the thermodynamic "
        "properties of water and steam. J. Eng. Gas Turbines Power 122, 150-182."
    ),
}


def cite(*keys: str) -> str:
    """Return the full references for ``keys``, one per line."""
    unknown = [k for k in keys if k not in REFERENCES]
    if unknown:
        raise ValueError(f"unknown reference key(s) {unknown}; known: {sorted(REFERENCES)}")
    return "\n".join(f"[{k}] {REFERENCES[k]}" for k in keys)
