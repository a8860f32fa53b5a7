(JOB TEST-1 PART FL-3004)
(ORDER QTY=2 MATERIAL AlMg3)
(SUBMITTED 1970-01-01 00:00:00 UTC BY test)
(MACHINE M02 LinuxCNC 2.9)
(FACE RO 70 RI 0 DEPTH 1.5 MM)
(TOOL EM-16 end-mill D16 CORNER R0.5 Z4)
(SPIRAL R1 80.0000 R2 0.0000 TURNS 9 STEP 8.8889 SENSE CW CLIMB)
(COVERAGE OK MAX GAP 0.0000 MM MAX DEVIATION 0.0050 MM TOLERANCE 0.005 MM)
(ORIGIN FACE CENTRE G54 Z0 ON THE FACE)
(CASES NONE CONFIDENCE 0.40)
(gearcam-model 0.1.0 gearcam-template 0.1.0)
(variable table: every shape, process and tool value is a named parameter)
#<r1> = 80  (tool-centre start radius R1, mm)
#<r2> = 0  (tool-centre end radius R2, mm)
#<theta0> = 0  (start angle, degrees)
#<total> = 3240  (sweep, degrees = 360 x turns)
#<chords> = 2529  (chords along the spiral, from the tolerance)
#<sense> = -1  (+1 counter-clockwise, -1 clockwise)
#<depth> = 1.5  (total depth below the face, mm)
#<passes> = 1  (depth passes)
#<feed> = 1599.5  (feed along the spiral, mm/min)
#<plunge> = 399.9  (plunge feed, mm/min)
#<rpm> = 3999  (spindle speed, rpm)
#<safe> = 5  (safe height above the face, mm)
G21 G90 G17 G94 G40 G49 G80
S[#<rpm>] M3
G0 Z[#<safe>]
#<pass> = 1
o100 while [#<pass> LE #<passes>]
  #<z> = [0 - #<depth> * #<pass> / #<passes>]
  G0 @[#<r1>] ^[#<theta0>]
  G1 Z[#<z>] F[#<plunge>]
  F[#<feed>]
  #<k> = 0
  o110 while [#<k> LT #<chords>]
    #<k> = [#<k> + 1]
    #<phi> = [#<total> * #<k> / #<chords>]
    G1 @[#<r1> + [#<r2> - #<r1>] * #<phi> / #<total>] ^[#<theta0> + #<sense> * #<phi>]
  o110 endwhile
  G0 Z[#<safe>]
  #<pass> = [#<pass> + 1]
o100 endwhile
M5
M2
