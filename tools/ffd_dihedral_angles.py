#!/usr/bin/env python3
"""Largest dihedral angle (degrees) of an FFD result, inside the panels and across the seams
between them, for the plain FFD (`deformed.obj`) and the restored mesh (`model.obj`) in
an output folder of `sheetform ffd` (vertices welded at 1e-5; needs numpy). Usage:
python3 tools/ffd_dihedral_angles.py OUT (docs/benchmarks-history.md, "Seams kept smooth")."""
import numpy as np, math, sys
from collections import defaultdict
def load(p):
    V=[];F=[]
    for l in open(p):
        if l.startswith('v '): V.append(list(map(float,l.split()[1:4])))
        elif l.startswith('f '): F.append([int(c.split('/')[0])-1 for c in l.split()[1:]])
    return np.array(V),F
def worst(p):
    V,F=load(p)
    key={}
    ids=[key.setdefault(tuple(np.round(v,5)),len(key)) for v in V]
    E=defaultdict(list)
    for fi,t in enumerate(F):
        t2=[ids[i] for i in t]
        for k in range(3): E[tuple(sorted((t2[k],t2[(k+1)%3])))].append(fi)
    def n(fi):
        a,b,c=V[F[fi]]; x=np.cross(b-a,c-a); return x/np.linalg.norm(x)
    w=0;ws=0
    for e,fs in E.items():
        if len(fs)==2:
            seam = len(set(F[fs[0]])&set(F[fs[1]]))<2
            ang=math.degrees(math.acos(max(-1,min(1,np.dot(n(fs[0]),n(fs[1]))))))
            if seam: ws=max(ws,ang)
            else: w=max(w,ang)
    return round(w,1),round(ws,1)
d=sys.argv[1]
print(d,'deformed (inside, seam)',worst(d+'/deformed.obj'),'restored',worst(d+'/model.obj'))
