#!/usr/bin/env python3
"""Total length of the chart borders of a flattened mesh: `model.obj` of `sheetform flatten`
holds each chart with its own vertices, so a border is a 3D edge that two boundary edges
share (vertices matched at 1e-6). Usage: python3 tools/chart_border_length.py OUT/model.obj
(docs/benchmarks-history.md, "Straight chart borders")."""
import sys, math
from collections import Counter
V=[];F=[]
for line in open(sys.argv[1]):
    if line.startswith('v '): V.append(tuple(map(float,line.split()[1:4])))
    elif line.startswith('f '):
        F.append([int(c.split('/')[0])-1 for c in line.split()[1:]])
c=Counter()
for t in F:
    for k in range(3):
        a,b=t[k],t[(k+1)%3]; c[(min(a,b),max(a,b))]+=1
key=lambda p: tuple(round(x,6) for x in p)
bd=Counter()
for (a,b),n in c.items():
    if n==1: bd[tuple(sorted([key(V[a]),key(V[b])]))]+=1
L=sum(math.dist(e[0],e[1]) for e,n in bd.items() if n==2)
print(round(L,1))
