#!/usr/bin/env python3
"""An IGSDB product JSON as the CSV vr-spectro reads: wavelength in
micrometres, T, Rf, Rb, with the product's thickness, conductivity and
coated side as comment lines.  "flip" as a third argument turns the pane
round (Rf and Rb swapped, the coated side with them).

usage: igsdb_csv.py PRODUCT.json OUT.csv [flip]"""
import json
import sys

d = json.load(open(sys.argv[1]))
flip = len(sys.argv) > 3 and sys.argv[3] == 'flip'
m = d['measured_data']
side = (d.get('coated_side') or 'neither').lower()
if flip:
    side = {'front': 'back', 'back': 'front'}.get(side, side)
with open(sys.argv[2], 'w') as o:
    o.write('# thickness: %r mm\n# conductivity: %r\n# coated side: %s\n'
            % (m['thickness'], m['conductivity'], side))
    o.write('wavelength_um,T,Rf,Rb\n')
    for r in d['spectral_data']['spectral_data']:
        f, b = (r['Rb'], r['Rf']) if flip else (r['Rf'], r['Rb'])
        o.write('%r,%r,%r,%r\n' % (r['wavelength'], r['T'], f, b))
